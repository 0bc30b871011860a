"""The single-step drag benchmark's metrics (upstream ScratchWorld's Table 2) as pure functions over rows.

One *run* is the effective final attempt of one drag job (``effective_rows``: latest attempt with a
verdict, else latest error), joined to the ``drags`` row of the same (job_id, attempt). Error runs
have no verdict: they are counted and listed by class but left out of every denominator, so the
infrastructure is never blamed on the model. A parse failure is a run: a failed one and a start miss.

A start *pass* is ``start_in_region or passed`` (upstream's Start Pass counts passed runs too). A run
that connects always pressed inside the start region, so this equals ``start_in_region``; a run where
it does not is named in the warnings (the region would be incomplete) rather than hidden.
"""

from __future__ import annotations

import statistics
from collections import Counter, defaultdict
from collections.abc import Iterable, Sequence

from pydantic import BaseModel, ConfigDict

from scratchworld_dist.kinds.drag._rows import DragRow
from scratchworld_dist.reports import ClassCount, class_counts, pass_at_k
from scratchworld_dist.results import JobRow, effective_rows

ALL = "ALL"
TYPES = ("T1", "T2")
"""Drag types in table order: T1 stacking, T2 nesting; ``ALL`` pools them."""

SETTINGS = ("baseline", "gt_start", "knowledge")
"""Settings in the paper's order."""


class DragRun(BaseModel):
    """One run: the job's effective row and, unless it ended in error, its drag row."""

    model_config = ConfigDict(frozen=True)

    job: JobRow
    drag: DragRow | None

    @property
    def error(self) -> bool:
        return self.job.outcome == "error"

    @property
    def passed(self) -> bool:
        return self.job.outcome == "passed"

    @property
    def drag_type(self) -> str:
        return self.drag.drag_type if self.drag is not None else self.job.category

    @property
    def start_pass(self) -> bool:
        return self.passed or (self.drag is not None and self.drag.start_in_region is True)


class PassAtK(BaseModel):
    """Pass@k at one k over the tasks of a cell, two ways."""

    k: int
    unbiased: float
    """Mean over tasks of Chen et al.'s estimator ``pass_at_k(n, c, k)`` (uses all n runs of a task)."""

    empirical: float
    """Upstream's: share of tasks where any of the first k runs (by seed) passed; depends on seed order."""


class Distance(BaseModel):
    """Distances in page px over the runs that missed, and how many of those had a measurable point."""

    mean: float | None
    median: float | None
    measured: int
    """Runs averaged: misses with a distance."""

    misses: int
    """Runs the distance is about (start misses, or good starts that did not connect)."""

    coverage: float | None
    """``measured / misses``; below 1 when some misses had no point (a parse failure); None without misses."""


class DragCell(BaseModel):
    """One (model, agent, setting) over one drag type (T1, T2) or all of them."""

    group: str
    tasks: int
    tasks_without_runs: int
    """Tasks whose every run ended in error: left out of Pass@k."""

    runs: int
    """Runs with a verdict (error runs excluded)."""

    passed: int
    error_runs: int
    errors: list[ClassCount]
    parse_failures: list[ClassCount]
    k_max: int
    """The fewest runs any task (with runs) has: Pass@k is given for k = 1..k_max."""

    pass_at_k: list[PassAtK]
    start_passes: int
    start_accuracy: float | None
    """``start_passes / runs``."""

    end_accuracy: float | None
    """``passed / start_passes``: connected given a good start."""

    start_error: Distance
    end_error: Distance
    """For the release translated by ``fixed_start - start``, over good starts that did not connect."""


class DragTableRow(BaseModel):
    """One (model, agent, setting): a row of Table 2, with one cell per group (T1, T2, ALL)."""

    model: str
    agent: str
    setting: str
    cells: list[DragCell]

    def cell(self, group: str) -> DragCell:
        return next(c for c in self.cells if c.group == group)


class DragTable(BaseModel):
    """The drag report: its runs, warnings, and one row per (model, agent, setting)."""

    version: int = 1
    runs: list[str]
    """The run directories read, as ``name (path)``."""

    warnings: list[str]
    rows: list[DragTableRow]


def join_runs(jobs: Iterable[JobRow], drags: Iterable[DragRow]) -> tuple[list[DragRun], list[str]]:
    """Effective drag runs, and warnings for rows that do not fit (non-drag jobs, verdicts without drag row)."""
    by_attempt = {(d.job_id, d.attempt): d for d in drags}
    runs: list[DragRun] = []
    others = orphans = mismatched = outside = 0
    for job in effective_rows(list(jobs)):
        if job.setting is None:
            others += 1
            continue
        drag = by_attempt.get((job.job_id, job.attempt))
        if job.outcome == "error":
            runs.append(DragRun(job=job, drag=None))
            continue
        if drag is None:
            orphans += 1
            continue
        run = DragRun(job=job, drag=drag)
        mismatched += drag.connected != run.passed
        outside += run.passed and drag.start_in_region is not True
        runs.append(run)
    identities = Counter((r.job.model, r.job.agent, r.job.setting, r.job.task_id, r.job.seed) for r in runs)
    twins = sum(n for n in identities.values() if n > 1)
    notes = [
        (twins, "run(s) share model, agent, setting, task and seed with another job (each counted; seed ties by id)"),
        (others, "job(s) that are not drag jobs (no setting) ignored"),
        (orphans, "drag job(s) with a verdict but no drags row for their attempt left out"),
        (mismatched, "drag row(s) whose connected flag disagrees with the job's outcome (the outcome counts)"),
        (outside, "passed run(s) pressed outside the start region (counted as start passes, as upstream does)"),
    ]
    return runs, [f"{n} {text}" for n, text in notes if n]


def drag_rows(runs: Sequence[DragRun]) -> list[DragTableRow]:
    """Table 2's rows: per (model, agent, setting), a cell per drag type seen (T1, T2 first) and ALL."""
    groups: dict[tuple[str, str, str], list[DragRun]] = defaultdict(list)
    for run in runs:
        groups[(run.job.model, run.job.agent, run.job.setting or "")].append(run)
    types = list(TYPES) + sorted({r.drag_type for r in runs} - set(TYPES))
    rows = [
        DragTableRow(
            model=model,
            agent=agent,
            setting=setting,
            cells=[drag_cell(t, [r for r in members if r.drag_type == t]) for t in types] + [drag_cell(ALL, members)],
        )
        for (model, agent, setting), members in groups.items()
    ]
    order = {s: i for i, s in enumerate(SETTINGS)}
    return sorted(rows, key=lambda r: (r.model, r.agent, order.get(r.setting, len(order)), r.setting))


def drag_cell(group: str, runs: Sequence[DragRun]) -> DragCell:
    """The metrics of one cell from its runs (error runs included; they are counted, not scored)."""
    scored = [r for r in runs if not r.error and r.drag is not None]
    per_task: dict[str, list[DragRun]] = {r.job.task_id: [] for r in runs}
    for run in scored:
        per_task[run.job.task_id].append(run)
    ordered = [sorted(task, key=lambda r: (r.job.seed, r.job.job_id)) for task in per_task.values() if task]
    k_max = min((len(task) for task in ordered), default=0)
    starts = [r for r in scored if r.start_pass]
    passed = sum(r.passed for r in scored)
    start_misses = [r for r in scored if not r.start_pass]
    end_misses = [r for r in starts if not r.passed]
    return DragCell(
        group=group,
        tasks=len(per_task),
        tasks_without_runs=len(per_task) - len(ordered),
        runs=len(scored),
        passed=passed,
        error_runs=sum(r.error for r in runs),
        errors=class_counts(r.job.error_class or "unknown" for r in runs if r.error),
        parse_failures=class_counts(r.drag.parse for r in scored if r.drag is not None and r.drag.parse != "ok"),
        k_max=k_max,
        pass_at_k=[_pass_at(ordered, k) for k in range(1, k_max + 1)],
        start_passes=len(starts),
        start_accuracy=_ratio(len(starts), len(scored)),
        end_accuracy=_ratio(passed, len(starts)),
        start_error=distance([r.drag.start_error_px for r in start_misses if r.drag is not None]),
        end_error=distance([r.drag.end_error_px for r in end_misses if r.drag is not None]),
    )


def distance(values: Sequence[float | None]) -> Distance:
    """Mean and median of the measured values among ``values`` (one per miss; None = no point)."""
    measured = [v for v in values if v is not None]
    return Distance(
        mean=statistics.fmean(measured) if measured else None,
        median=statistics.median(measured) if measured else None,
        measured=len(measured),
        misses=len(values),
        coverage=_ratio(len(measured), len(values)),
    )


def _pass_at(tasks: Sequence[Sequence[DragRun]], k: int) -> PassAtK:
    """Both Pass@k over tasks whose runs are in seed order (every task has at least k runs)."""
    unbiased = [pass_at_k(len(task), sum(r.passed for r in task), k) for task in tasks]
    empirical = [any(r.passed for r in task[:k]) for task in tasks]
    return PassAtK(k=k, unbiased=statistics.fmean(unbiased), empirical=statistics.fmean(empirical))


def _ratio(part: int, whole: int) -> float | None:
    return part / whole if whole else None
