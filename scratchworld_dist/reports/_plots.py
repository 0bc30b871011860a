"""The report's plots as data with inline SVG, and as an HTML fragment for the report page and the viewer.

matplotlib is imported only when plots are drawn (``report_plots``): the Markdown and JSON reports
and ``status`` stay light. The fragment is static SVG and tables with no script and no external
resource, so a page works from ``file://`` and offline.
"""

from __future__ import annotations

import html
from collections.abc import Sequence
from pathlib import Path

from pydantic import BaseModel

from scratchworld_dist.reports._plot_data import plot_data
from scratchworld_dist.reports._runs import load_runs
from scratchworld_dist.results import JobRow


class Plot(BaseModel):
    """One drawn plot and the table of the numbers it shows."""

    key: str
    """Stable name: ``sr_by_category``, ``reasoning_acting_gap``, ``cost_vs_sr``, ``pass_at_k``,
    ``steps_to_success`` or ``errors_over_time``."""

    title: str
    caption: str
    """What is shown, in a sentence."""

    svg: str
    """An ``<svg>`` element to inline in HTML (its text is escaped by matplotlib)."""

    headers: list[str]
    rows: list[list[str]]
    """Exactly the numbers drawn, as text (user-provided strings unescaped)."""


def report_plots(run_dirs: Sequence[Path], *, force: bool = False) -> list[Plot]:
    """The plots of the runs' episode results; those with nothing to show are left out, drag runs get none.

    Runs are read and checked as for ``build_report`` (``RunDirError`` when they cannot be read or
    merged without ``force``).
    """
    runs, _ = load_runs(run_dirs, force=force)
    return plots_of([row for run in runs for row in run.rows])


def plots_of(rows: Sequence[JobRow]) -> list[Plot]:
    """The plots of attempt rows already read (each job counts once, as in ``report_plots``)."""
    data = plot_data(rows)
    if not data:
        return []
    from scratchworld_dist.reports._plot_draw import draw_svg  # imports matplotlib: only when drawing

    return [
        Plot(key=d.key, title=d.title, caption=d.caption, svg=draw_svg(d), headers=d.headers, rows=d.rows) for d in data
    ]


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
