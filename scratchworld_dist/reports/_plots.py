"""Plots any report can show: what one plot draws and the table of its numbers (``PlotData``), the plot drawn as
inline SVG (``Plot``), and plots as an HTML fragment for a report page and the viewer.

Each plot is data first, so a reader (or a screen reader, or a test) gets the values without reading them off a
chart; a kind computes its plots' data (the episodes' SR by category, cost vs SR...) and ``draw_plots``
(``_plot_draw``) draws them. Only drawing imports matplotlib: the Markdown and JSON reports and ``status`` stay
light. The fragment is
static SVG and tables with no script and no external resource, so a page works from ``file://`` and offline.
"""

from __future__ import annotations

import html
from collections.abc import Sequence
from typing import Literal

from pydantic import BaseModel

PlotKind = Literal["bars", "front", "lines", "boxes", "stacked"]


class Series(BaseModel):
    """One named series: a value per tick (``None`` where it has none)."""

    name: str
    values: list[float | None]


class Point(BaseModel):
    """One named point of a ``front`` plot (the episodes': an agent/model and mode at its cost and SR)."""

    name: str
    x: float
    y: float
    front: bool
    """On the Pareto front, which the plot joins: no other point has a higher ``y`` for at most its ``x``."""


class Box(BaseModel):
    """One distribution of a ``boxes`` plot (the episodes': steps to success), whiskers at min and max."""

    name: str
    n: int
    low: float
    q1: float
    median: float
    q3: float
    high: float
    mean: float


class PlotData(BaseModel):
    """One plot: what it shows, how it is drawn, and the table of its numbers."""

    key: str
    title: str
    caption: str
    kind: PlotKind
    x_label: str
    y_label: str
    ticks: list[str] = []
    """Categorical x positions of ``bars``, ``lines`` and ``stacked``."""

    series: list[Series] = []
    notes: list[str] = []
    """Text drawn above each tick (``bars``), e.g. the gap between two bars."""

    points: list[Point] = []
    boxes: list[Box] = []
    headers: list[str]
    rows: list[list[str]]


class Plot(BaseModel):
    """One drawn plot and the table of the numbers it shows."""

    key: str
    """Stable name (the episodes': ``sr_by_category``, ``reasoning_acting_gap``, ``cost_vs_sr``, ``pass_at_k``,
    ``steps_to_success`` or ``errors_over_time``)."""

    title: str
    caption: str
    """What is shown, in a sentence."""

    svg: str
    """An ``<svg>`` element to inline in HTML (its text is escaped by matplotlib)."""

    headers: list[str]
    rows: list[list[str]]
    """Exactly the numbers drawn, as text (user-provided strings unescaped)."""


def plots_html(plots: Sequence[Plot]) -> str:
    """A ``<section>`` with a ``<figure>`` per plot: the SVG, its caption and a table of its numbers beside it."""
    if not plots:
        return ""
    figures = "\n".join(_figure(plot) for plot in plots)
    return f'<section class="sw-plots">\n{_STYLE}\n<h2>Plots</h2>\n{figures}\n</section>'


def _figure(plot: Plot) -> str:
    head = "".join(f"<th>{html.escape(cell)}</th>" for cell in plot.headers)
    body = "".join("<tr>" + "".join(f"<td>{html.escape(c)}</td>" for c in row) + "</tr>" for row in plot.rows)
    return (
        f'<figure id="plot-{html.escape(plot.key)}">\n'
        f"<figcaption><strong>{html.escape(plot.title)}</strong>. {html.escape(plot.caption)}</figcaption>\n"
        f'<div class="sw-plot">{plot.svg}</div>\n'
        f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>\n"
        "</figure>"
    )


_STYLE = """<style>
.sw-plots figure { display: flex; flex-wrap: wrap; align-items: flex-start; gap: 1em; margin: 1.5em 0; }
.sw-plots figcaption { flex-basis: 100%; }
.sw-plots .sw-plot { flex: 1 1 36em; max-width: 52em; }
.sw-plots svg { width: 100%; height: auto; }
.sw-plots table { border-collapse: collapse; font-size: 0.9em; }
.sw-plots th, .sw-plots td { border: 1px solid #ccc; padding: 0.2em 0.5em; text-align: right; }
.sw-plots th:first-child, .sw-plots td:first-child { text-align: left; }
</style>"""
