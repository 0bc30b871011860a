"""Drawing ``PlotData`` with matplotlib as SVG strings to inline in a page.

Only ``Figure`` and its SVG printer are used, never pyplot, so no GUI backend is ever picked and
nothing global changes. Text stays text (``svg.fonttype = none``: searchable, small, escaped by
matplotlib's SVG writer). The id salt is fixed and the metadata has no date, so the same numbers
give the same bytes; ids are prefixed by the plot's key, so plots on one page never share one.
Importing this module imports matplotlib: import it only to draw.
"""

from __future__ import annotations

import io
import re
from collections.abc import Sequence

import matplotlib as mpl
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from scratchworld_dist.reports._plots import Plot, PlotData

_PALETTE = mpl.colormaps["tab10"].colors
_SIZE = (7.0, 3.8)
_RC = {
    "svg.fonttype": "none",
    "svg.hashsalt": "scratchworld",
    "font.size": 9,
    "axes.spines.top": False,
    "axes.spines.right": False,
}


def draw_plots(data: Sequence[PlotData]) -> list[Plot]:
    """Each plot's data drawn, with the table of its numbers."""
    return [
        Plot(key=d.key, title=d.title, caption=d.caption, svg=draw_svg(d), headers=d.headers, rows=d.rows) for d in data
    ]


def draw_svg(data: PlotData) -> str:
    """The plot as an ``<svg>`` element (no XML prologue, no metadata), the same bytes for the same data."""
    with mpl.rc_context(_RC):
        figure = Figure(figsize=_SIZE, layout="constrained")
        axes = figure.add_subplot()
        _DRAW[data.kind](axes, data)
        axes.set_title(_text(data.title))
        axes.set_xlabel(_text(data.x_label))
        axes.set_ylabel(_text(data.y_label))
        buffer = io.StringIO()
        figure.savefig(buffer, format="svg", bbox_inches="tight", metadata={"Date": None, "Creator": None})
    return _inline(buffer.getvalue(), data.key)


def _bars(axes: Axes, data: PlotData) -> None:
    count = max(len(data.series), 1)
    width = 0.8 / count
    for i, series in enumerate(data.series):
        xs = [t + (i - (count - 1) / 2) * width for t in range(len(data.ticks))]
        heights = [float("nan") if v is None else v for v in series.values]
        axes.bar(xs, heights, width, label=_text(series.name), color=_color(i))
    for t, note in enumerate(data.notes):
        top = max((s.values[t] or 0.0 for s in data.series), default=0.0)
        axes.annotate(_text(note), (t, top), xytext=(0, 3), textcoords="offset points", ha="center", va="bottom")
    axes.set_xticks(range(len(data.ticks)), [_text(t) for t in data.ticks])
    axes.set_ylim(0, 110 if data.notes else 100)
    _legend(axes, count)


def _front(axes: Axes, data: PlotData) -> None:
    for i, point in enumerate(data.points):
        marker = "o" if point.front else "x"
        axes.scatter([point.x], [point.y], marker=marker, color=_color(i), label=_text(point.name), zorder=3)
    front = sorted((p for p in data.points if p.front), key=lambda p: p.x)
    axes.step([p.x for p in front], [p.y for p in front], where="post", color="0.4", linestyle="--", zorder=2)
    axes.set_ylim(0, 100)
    axes.set_xlim(left=0)
    _legend(axes, len(data.points))


def _lines(axes: Axes, data: PlotData) -> None:
    ks = [int(t) for t in data.ticks]
    for i, series in enumerate(data.series):
        ys = [float("nan") if v is None else v for v in series.values]
        axes.plot(ks[: len(ys)], ys, marker="o", color=_color(i), label=_text(series.name))
    axes.set_xticks(ks)
    axes.set_ylim(0, 105)
    _legend(axes, len(data.series))


def _boxes(axes: Axes, data: PlotData) -> None:
    stats = [
        {"label": _text(b.name), "whislo": b.low, "q1": b.q1, "med": b.median, "q3": b.q3, "whishi": b.high}
        | {"mean": b.mean, "fliers": []}
        for b in data.boxes
    ]
    axes.bxp(stats, showmeans=True, meanprops={"marker": "D", "markerfacecolor": "white"})
    axes.tick_params(axis="x", labelrotation=15)
    axes.set_ylim(bottom=0)


def _stacked(axes: Axes, data: PlotData) -> None:
    bottom = [0.0] * len(data.ticks)
    for i, series in enumerate(data.series):
        heights = [v or 0.0 for v in series.values]
        axes.bar(range(len(data.ticks)), heights, 0.8, bottom=bottom, label=_text(series.name), color=_color(i))
        bottom = [b + h for b, h in zip(bottom, heights, strict=True)]
    step = -(-len(data.ticks) // 6)  # at most six labels, so they stay readable (the table has every bin)
    shown = range(0, len(data.ticks), step)
    axes.set_xticks(list(shown), [data.ticks[i] for i in shown], rotation=20, ha="right")
    axes.yaxis.get_major_locator().set_params(integer=True)
    _legend(axes, len(data.series))


_DRAW = {"bars": _bars, "front": _front, "lines": _lines, "boxes": _boxes, "stacked": _stacked}


def _legend(axes: Axes, entries: int) -> None:
    """Below the axes, so long model names take the page's width and not the plot's."""
    if entries:
        axes.figure.legend(loc="outside lower center", ncols=min(entries, 2), frameon=False)


def _color(index: int) -> tuple[float, float, float]:
    return _PALETTE[index % len(_PALETTE)]


def _text(value: str) -> str:
    """Literal text for matplotlib: a ``$`` in a model name would start mathtext (and may fail to parse)."""
    return value.replace("$", r"\$")


def _inline(svg: str, key: str) -> str:
    """The ``<svg>`` element alone, its ids prefixed by ``key``.

    The XML prologue, doctype and RDF metadata mean nothing inline in HTML, and matplotlib names
    every figure's groups alike (``axes_1``, ...): ids must be unique on a page holding several.
    """
    element = svg[svg.index("<svg") :]
    element = re.sub(r"\s*<metadata>.*?</metadata>", "", element, flags=re.DOTALL).strip()
    element = re.sub(r'\bid="([^"]+)"', rf'id="{key}-\1"', element)
    return re.sub(r'(href="#|url\(#)([^")]+)', rf"\g<1>{key}-\2", element)
