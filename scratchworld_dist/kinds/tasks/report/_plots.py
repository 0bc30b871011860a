"""The episode report's plots: their numbers computed without drawing anything, and drawn.

Each plot is a ``PlotData`` (``scratchworld_dist.reports``): what to draw and a table of exactly the numbers
drawn. Rates come from ``summarize`` over the effective rows (one per job), as in the report's tables, so a bar
and the main table never disagree. A plot with nothing to show (no primitive mode for the gap, one seed for
pass@k, no error for errors over time) is left out rather than drawn empty.
"""

from __future__ import annotations

import statistics
from collections import Counter, defaultdict
from collections.abc import Sequence
from datetime import UTC, datetime, timedelta
from pathlib import Path

from scratchworld_dist.kinds import DEFAULT_KIND, UnknownKindError, job_kind
from scratchworld_dist.kinds.tasks.report._summary import DETERMINATE, ReportRow, ordered_categories, summarize
from scratchworld_dist.reports import Box, Plot, PlotData, Point, Series, load_runs, mean_pass_at_k
from scratchworld_dist.results import JobRow, effective_rows

_BIN_WIDTHS_S = (60, 300, 600, 900, 1800, 3600, 7200, 10800, 21600, 43200, 86400, 172800, 604800)
"""Bin widths errors over time may use, from one minute to a week: the smallest that fits."""

MAX_BINS = 30
"""Errors over time get at most this many bins (wider ones past a week's width, in whole days)."""


def _episodes(kind: str) -> bool:
    """Whether jobs of ``kind`` are episodes (a kind no longer installed: not known to be)."""
    try:
        return bool(getattr(job_kind(kind), "episodes", False))
    except UnknownKindError:
        return False


def plot_data(attempts: Sequence[JobRow]) -> list[PlotData]:
    """Every plot the attempt rows of an episode run can show; ``[]`` for runs of another kind (a drag run has
    Table 2)."""
    kinds = {r.benchmark or DEFAULT_KIND for r in attempts}  # rows older than the column: the default kind's
    if not attempts or not all(_episodes(name) for name in kinds):
        return []
    effective = list(effective_rows(list(attempts)))
    groups: dict[tuple[str, str, str], list[JobRow]] = defaultdict(list)
    for row in effective:
        groups[(row.agent, row.model, row.mode)].append(row)
    summaries = sorted(
        ((summarize(*group, rows, None), rows) for group, rows in groups.items()),
        key=lambda pair: (pair[0].mode, pair[0].label),
    )
    categories = ordered_categories({r.category for r in effective})
    plots = [
        sr_by_category([s for s, _ in summaries], categories),
        reasoning_acting_gap([s for s, _ in summaries]),
        cost_vs_sr([s for s, _ in summaries]),
        pass_at_k_curves(summaries),
        steps_to_success(summaries),
        errors_over_time(attempts),
    ]
    return [plot for plot in plots if plot is not None]


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
    from scratchworld_dist.reports import draw_plots  # imports matplotlib: only when drawing

    return draw_plots(data)


def sr_by_category(rows: Sequence[ReportRow], categories: Sequence[str]) -> PlotData | None:
    """The paper's Table 1 as bars: SR per category and overall, one bar per agent/model and mode."""
    if not any(row.determinate for row in rows):
        return None
    table = []
    series = []
    for row in rows:
        stats = [row.categories.get(c) for c in categories]
        values = [s.sr if s else None for s in stats] + [row.sr]
        series.append(Series(name=_name(row), values=_percent(values)))
        cells = [_rate(s.passed, s.determinate) if s else "-" for s in stats] + [_rate(row.passed, row.determinate)]
        table.append([row.label, row.mode, *cells])
    return PlotData(
        key="sr_by_category",
        title="Success rate by category",
        caption="SR (passed / jobs with a verdict) per task category and overall, per agent/model and mode; "
        "jobs that ended in error have no verdict and are left out.",
        kind="bars",
        x_label="category",
        y_label="SR (%)",
        ticks=[*categories, "overall"],
        series=series,
        headers=["agent/model", "mode", *categories, "overall"],
        rows=table,
    )


def reasoning_acting_gap(rows: Sequence[ReportRow]) -> PlotData | None:
    """Composite vs primitive SR of each agent/model that ran both: the gap is composite - primitive."""
    by_mode = {(row.label, row.mode): row for row in rows}
    labels = sorted({row.label for row in rows})
    pairs = [
        (label, by_mode[(label, "composite")], by_mode[(label, "primitive")])
        for label in labels
        if (label, "composite") in by_mode and (label, "primitive") in by_mode
    ]
    pairs = [(label, c, p) for label, c, p in pairs if c.sr is not None and p.sr is not None]
    if not pairs:
        return None
    gaps = [_points(c.sr - p.sr) for _, c, p in pairs if c.sr is not None and p.sr is not None]
    return PlotData(
        key="reasoning_acting_gap",
        title="Reasoning-acting gap",
        caption="SR in composite mode (blocks by name) and primitive mode (mouse and keyboard) per agent/model; "
        "the gap is composite SR - primitive SR in percentage points.",
        kind="bars",
        x_label="agent/model",
        y_label="SR (%)",
        ticks=[label for label, _, _ in pairs],
        series=[
            Series(name="composite", values=_percent([c.sr for _, c, _ in pairs])),
            Series(name="primitive", values=_percent([p.sr for _, _, p in pairs])),
        ],
        notes=gaps,
        headers=["agent/model", "composite SR", "primitive SR", "gap (composite - primitive)"],
        rows=[
            [label, _rate(c.passed, c.determinate), _rate(p.passed, p.determinate), gap]
            for (label, c, p), gap in zip(pairs, gaps, strict=True)
        ],
    )


def cost_vs_sr(rows: Sequence[ReportRow]) -> PlotData | None:
    """Total cost against SR per agent/model and mode, with the Pareto front (most SR for least cost)."""
    rated = [row for row in rows if row.sr is not None]
    if not any(row.cost_usd > 0 for row in rated):
        return None  # scripted agents only: every point at $0
    front = pareto_front([(row.cost_usd, row.sr or 0.0) for row in rated])
    points = [
        Point(name=_name(row), x=row.cost_usd, y=(row.sr or 0.0) * 100, front=i in front) for i, row in enumerate(rated)
    ]
    return PlotData(
        key="cost_vs_sr",
        title="Cost vs success rate",
        caption="Total model cost of each agent/model and mode (its effective attempts, errors included) against "
        "its SR; the step line is the Pareto front: no other point has a higher SR for at most its cost.",
        kind="front",
        x_label="cost (USD)",
        y_label="SR (%)",
        points=points,
        headers=["agent/model", "mode", "cost (USD)", "SR", "Pareto front"],
        rows=[
            [row.label, row.mode, _usd(row.cost_usd), _rate(row.passed, row.determinate), "yes" if p.front else "no"]
            for row, p in zip(rated, points, strict=True)
        ],
    )


def pareto_front(points: Sequence[tuple[float, float]]) -> set[int]:
    """Indices of the (cost, SR) points no other point beats: none has a higher SR for at most the cost.

    Of points with equal cost and SR the first is on the front, so the step line has no repeats.
    """
    order = sorted(range(len(points)), key=lambda i: (points[i][0], -points[i][1], i))
    front: set[int] = set()
    best = float("-inf")
    for i in order:
        if points[i][1] > best:
            front.add(i)
            best = points[i][1]
    return front


def pass_at_k_curves(summaries: Sequence[tuple[ReportRow, list[JobRow]]]) -> PlotData | None:
    """pass@k for k = 1..seeds of each agent/model and mode run with more than one seed."""
    curves = []
    for row, rows in summaries:
        seeds = len({r.seed for r in rows})
        if seeds < 2:
            continue
        per_task: dict[str, list[bool]] = defaultdict(list)
        for r in rows:
            if r.outcome in DETERMINATE:
                per_task[r.task_id].append(r.outcome == "passed")
        counts = [(len(v), sum(v)) for v in per_task.values()]
        curves.append((row, [mean_pass_at_k(counts, k) for k in range(1, seeds + 1)]))
    curves = [(row, values) for row, values in curves if any(v is not None for v in values)]
    if not curves:
        return None
    most = max(len(values) for _, values in curves)
    return PlotData(
        key="pass_at_k",
        title="pass@k",
        caption="Chance that at least one of k attempts (seeds) at a task passes, averaged over tasks with at least "
        "k attempts with a verdict (unbiased estimator), for k = 1 up to the number of seeds.",
        kind="lines",
        x_label="k (attempts per task)",
        y_label="pass@k (%)",
        ticks=[str(k) for k in range(1, most + 1)],
        series=[Series(name=_name(row), values=_percent(values)) for row, values in curves],
        headers=["agent/model", "mode", *(f"pass@{k}" for k in range(1, most + 1))],
        rows=[
            [row.label, row.mode, *(_pct(v) for v in values), *(["-"] * (most - len(values)))] for row, values in curves
        ],
    )


def steps_to_success(summaries: Sequence[tuple[ReportRow, list[JobRow]]]) -> PlotData | None:
    """The distribution of agent steps over passed jobs, per agent/model and mode."""
    boxes = []
    labels = []
    for row, rows in summaries:
        steps = sorted(float(r.steps) for r in rows if r.outcome == "passed")
        if steps:
            boxes.append(_box(_name(row), steps))
            labels.append((row.label, row.mode))
    if not boxes:
        return None
    return PlotData(
        key="steps_to_success",
        title="Steps to success",
        caption="Agent steps of the jobs that passed, per agent/model and mode: the box spans the quartiles, the "
        "line is the median, the diamond the mean and the whiskers reach the fewest and most steps.",
        kind="boxes",
        x_label="agent/model (mode)",
        y_label="steps",
        boxes=boxes,
        headers=["agent/model", "mode", "successes", "min", "Q1", "median", "Q3", "max", "mean"],
        rows=[
            [label, mode, str(b.n), *(f"{v:.1f}" for v in (b.low, b.q1, b.median, b.q3, b.high, b.mean))]
            for (label, mode), b in zip(labels, boxes, strict=True)
        ],
    )


def errors_over_time(attempts: Sequence[JobRow]) -> PlotData | None:
    """Error attempts (retried ones too) per time bin of when they finished, stacked by error class."""
    distinct = list({(r.job_id, r.attempt): r for r in attempts}.values())
    errors = [r for r in distinct if r.outcome == "error"]
    if not errors:
        return None
    first = min(r.finished_at for r in distinct)
    last = max(r.finished_at for r in distinct)
    width = bin_width(last - first)
    start = _floor(first, width)
    bins = int((last - start) / width) + 1
    counts: dict[str, Counter[int]] = defaultdict(Counter)
    for row in errors:
        counts[row.error_class or "unknown"][int((row.finished_at - start) / width)] += 1
    classes = sorted(counts, key=lambda c: (-sum(counts[c].values()), c))
    starts = [start + i * width for i in range(bins)]
    ticks = [_when(t, width) for t in starts]
    return PlotData(
        key="errors_over_time",
        title="Errors over time",
        caption=f"Attempts that ended in error (retried ones too), by when they finished, in bins of "
        f"{_duration(width)} (UTC) over the run's span, stacked by error class.",
        kind="stacked",
        x_label=f"finished (UTC, bins of {_duration(width)})",
        y_label="error attempts",
        ticks=ticks,
        series=[Series(name=c, values=[float(counts[c][i]) for i in range(bins)]) for c in classes],
        headers=["bin start (UTC)", *classes, "total"],
        rows=[
            [tick, *(str(counts[c][i]) for c in classes), str(sum(counts[c][i] for c in classes))]
            for i, tick in enumerate(ticks)
        ],
    )


def bin_width(span: timedelta) -> timedelta:
    """The smallest usual width that covers ``span`` in at most ``MAX_BINS`` bins (whole days past a week)."""
    for seconds in _BIN_WIDTHS_S:
        if span < timedelta(seconds=seconds * MAX_BINS):
            return timedelta(seconds=seconds)
    days = span // timedelta(days=MAX_BINS) + 1
    return timedelta(days=days)


def _floor(moment: datetime, width: timedelta) -> datetime:
    """``moment`` rounded down to a multiple of ``width`` since the epoch, so bins start at round times."""
    epoch = datetime(1970, 1, 1, tzinfo=UTC)
    return epoch + ((moment - epoch) // width) * width


def _when(moment: datetime, width: timedelta) -> str:
    return moment.astimezone(UTC).strftime("%Y-%m-%d" if width >= timedelta(days=1) else "%Y-%m-%d %H:%M")


def _duration(width: timedelta) -> str:
    seconds = int(width.total_seconds())
    for unit, size in (("day", 86400), ("h", 3600), ("min", 60)):
        if seconds % size == 0:
            n = seconds // size
            return f"{n} {unit}{'s' * (unit == 'day' and n != 1)}"
    return f"{seconds} s"


def _box(name: str, steps: Sequence[float]) -> Box:
    q1, median, q3 = statistics.quantiles(steps, n=4, method="inclusive") if len(steps) > 1 else [steps[0]] * 3
    return Box(
        name=name, n=len(steps), low=steps[0], q1=q1, median=median, q3=q3, high=steps[-1], mean=statistics.mean(steps)
    )


def _name(row: ReportRow) -> str:
    return f"{row.label} ({row.mode})"


def _percent(values: Sequence[float | None]) -> list[float | None]:
    return [None if v is None else v * 100 for v in values]


def _pct(value: float | None) -> str:
    return "-" if value is None else f"{value * 100:.1f}%"


def _points(value: float) -> str:
    return f"{value * 100:+.1f} pp"


def _rate(passed: int, determinate: int) -> str:
    return "-" if not determinate else f"{_pct(passed / determinate)} ({passed}/{determinate})"


def _usd(value: float) -> str:
    return f"${value:,.2f}" if value >= 1 else f"${value:.4f}"
