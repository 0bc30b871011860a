"""The drag benchmark's report: read run directories into a ``DragTable`` and draw it like the paper's Table 2.

Run directories are loaded as for the main report (manifest required, rows of an older suite or
harness set aside, incomparable runs refused unless forced); the ``drags`` table adds each run's
points and distances. HTML is the Markdown in a ``<pre>``: one rendering to keep in step.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from scratchworld_dist._errors import RunDirError
from scratchworld_dist.kinds.drag._metrics import (
    ALL,
    Distance,
    DragCell,
    DragTable,
    DragTableRow,
    drag_rows,
    join_runs,
)
from scratchworld_dist.kinds.drag._rows import DragRow
from scratchworld_dist.reports import (
    LoadedRun,
    ReportFormat,
    load_runs,
    markdown_table,
    read_rows,
    render_text,
    row_label,
    stale_warnings,
)
from scratchworld_dist.results import RunStore
from scratchworld_dist.sweep import NO_MODEL

_DEFINITIONS = (
    "One run = the final attempt of one drag job (model, agent, setting, task, seed). Error runs (no verdict, e.g. "
    "the model was unreachable) are counted under Counts and left out of every rate. Pass@k = mean over tasks of the "
    "unbiased estimator 1 - C(n-c, k)/C(n, k) from all n runs of a task, for k up to the fewest runs any task has; "
    "the upstream table is the share of tasks where any of the first k runs by seed passed. Start acc. = runs "
    "pressing inside the start region (or passing) / runs; a parse failure is a start miss. End acc. = passed / "
    "good starts. Start err = mean px from the press to the start region over start misses with a point; End err = "
    "mean px from the release, moved by fixed start - press, to the end region over good starts that did not "
    "connect. Distances shows medians and how many misses had a point."
)


def is_drag_run(run_dir: Path) -> bool:
    """Whether a run directory holds drag jobs: drags rows, or jobs with a setting (all of them errors)."""
    store = RunStore(run_dir)
    if store.read_table("drags", columns=["job_id"]).num_rows:
        return True
    return any(s is not None for s in store.read_table("jobs", columns=["setting"]).column("setting").to_pylist())


def build_drag_report(run_dirs: list[Path], *, force: bool = False) -> DragTable:
    """Merge the drag results of ``run_dirs``; raises ``RunDirError`` when they hold no drag job."""
    loaded, warnings = load_runs(run_dirs, force=force)
    return drag_table_of(loaded, warnings)


def drag_table_of(loaded: Sequence[LoadedRun], warnings: list[str], rows: Sequence[DragRow] | None = None) -> DragTable:
    """The drag table of runs already loaded and checked for merging (``warnings``: those of the check;
    ``rows``: their ``drags`` rows, when read already)."""
    warnings = warnings + stale_warnings(loaded)
    jobs = [row for run in loaded for row in run.rows]
    if rows is None:  # not read already (the diagnosis reads each group's rows once, for both)
        rows = [d for run in loaded for d in read_drag_rows(run.path)]
    runs, notes = join_runs(jobs, rows)
    if not runs:
        raise RunDirError(f"{', '.join(str(r.path) for r in loaded)}: no drag job results")
    return DragTable(runs=[r.name for r in loaded], warnings=warnings + notes, rows=drag_rows(runs))


def read_drag_rows(run_dir: Path) -> list[DragRow]:
    """The ``drags`` rows of a run directory (``RunDirError`` for a row that is not one)."""
    return read_rows(run_dir, "drags", DragRow, "a drag")


def render_drag(table: DragTable, fmt: ReportFormat) -> str:
    """The drag report as text in ``fmt`` (``md``, ``html`` or ``json``)."""
    return render_text(table, lambda: render_drag_markdown(table), fmt)


def render_drag_markdown(table: DragTable) -> str:
    parts = ["# ScratchWorld single-step drag report"]
    parts += [f"Warning: {w}" for w in table.warnings]
    parts.append("Runs: " + "; ".join(table.runs))
    groups = [c.group for c in table.rows[0].cells] if table.rows else [ALL]
    width = max([1] + [c.k_max for row in table.rows for c in row.cells])
    several = len({r.agent for r in table.rows}) > 1
    ks = range(1, width + 1)

    def label(row: DragTableRow) -> list[str]:
        scripted = row.model == NO_MODEL  # a scripted agent has no model: name the agent
        return [row_label(row.agent, row.model) if several or scripted else row.model, row.setting]

    main_cols = [*(f"Pass@{k}" for k in ks), "Start acc.", "End acc.", "Start err (px)", "End err (px)"]
    main = [[*label(row), *(v for c in row.cells for v in _main_cells(c, width))] for row in table.rows]
    main_header = ["model", "setting", *(f"{g} {c}" for g in groups for c in main_cols)]
    parts += ["## Table 2", markdown_table(main_header, main)]
    upstream = [[*label(row), *(v for c in row.cells for v in _pass_cells(c, width, True))] for row in table.rows]
    parts.append("## Pass@k as upstream computes it (any of the first k runs by seed passed)")
    parts.append(markdown_table(["model", "setting", *(f"{g} Pass@{k}" for g in groups for k in ks)], upstream))
    dist_cols = ["group", "start err mean", "median", "measured/misses", "end err mean", "median", "measured/misses"]
    dist = [[*label(row), c.group, *_dist(c.start_error), *_dist(c.end_error)] for row in table.rows for c in row.cells]
    parts += ["## Distances (px)", markdown_table(["model", "setting", *dist_cols], dist)]
    parts += ["## Counts", "\n".join(f"- {' / '.join(label(row))}: {_counts(row.cell(ALL))}" for row in table.rows)]
    parts.append(_DEFINITIONS)
    return "\n\n".join(parts) + "\n"


def _main_cells(cell: DragCell, width: int) -> list[str]:
    return [
        *_pass_cells(cell, width, False),
        _rate(cell.start_passes, cell.runs),
        _rate(cell.passed, cell.start_passes),
        _px(cell.start_error.mean),
        _px(cell.end_error.mean),
    ]


def _pass_cells(cell: DragCell, width: int, empirical: bool) -> list[str]:
    values = [_pct(p.empirical if empirical else p.unbiased) for p in cell.pass_at_k]
    return values + ["-"] * (width - len(values))


def _dist(d: Distance) -> list[str]:
    return [_px(d.mean), _px(d.median), f"{d.measured}/{d.misses}"]


def _counts(cell: DragCell) -> str:
    text = f"{cell.tasks} tasks, {cell.runs} runs ({cell.passed} passed)"
    errors = ", ".join(f"{e.name} {e.runs}" for e in cell.errors)
    text += f"; {cell.error_runs} error runs" + (f" ({errors})" if errors else "")
    parse = ", ".join(f"{p.name} {p.runs}" for p in cell.parse_failures)
    text += f"; parse failures: {parse or 'none'}"
    if cell.tasks_without_runs:
        text += f"; {cell.tasks_without_runs} task(s) with only error runs (left out of Pass@k)"
    return text


def _pct(value: float | None) -> str:
    return "-" if value is None else f"{value * 100:.1f}%"


def _rate(part: int, whole: int) -> str:
    return "-" if not whole else f"{_pct(part / whole)} ({part}/{whole})"


def _px(value: float | None) -> str:
    return "-" if value is None else f"{value:.1f}"
