"""The task-episode columns of the diagnosis table: composite and primitive SR, and the gap between them,
which is what GUI control costs a model."""

from __future__ import annotations

import statistics
from collections.abc import Sequence
from typing import Any

from pydantic import BaseModel

from scratchworld_dist.kinds.tasks.report import (
    DETERMINATE,
    RunReport,
    render_html_body,
    render_markdown,
    report_of,
    report_plots,
)
from scratchworld_dist.reports import MISSING, Rate, ReportFormat, RunGroup, mean_interval, plots_html, rate_cell
from scratchworld_dist.results import JobRow, effective_rows


class Gap(BaseModel):
    """Composite SR minus primitive SR, in percentage points."""

    points: float
    half_width: float | None
    """Of the 95% t interval over per-seed gaps, in points; None with fewer than two seeds."""

    seeds: int
    """Seeds with verdicts in both modes. With two or more, ``points`` is the mean of the per-seed gaps;
    else it is the difference of the pooled SRs."""


class TasksCells(BaseModel):
    """The episode cells of a diagnosis row."""

    composite_sr: Rate | None = None
    primitive_sr: Rate | None = None
    gap: Gap | None = None


class TasksSection(BaseModel):
    """The episode report's place in the report over several kinds."""

    episodes: RunReport | None = None


class TasksDiagnosis:
    """Each model's decided episode jobs, per mode."""

    cells_model = TasksCells
    axes_model = None
    section_model = TasksSection
    runs_label = "Episode runs"
    definitions = (
        "Composite and primitive SR = passed / decided episode jobs. Gap = composite SR - primitive SR in "
        "percentage points: with two or more seeds decided in both modes, the mean of the per-seed gaps ± the "
        "half-width of its 95% t interval; with fewer, the difference of the pooled SRs, without an interval."
    )

    def units(self, group: RunGroup) -> list[tuple[str, Any]]:
        jobs = [row for run in group.runs for row in run.rows]
        return [(row.job_id, row) for row in effective_rows(jobs)]

    def cells(self, units: Sequence[JobRow]) -> TasksCells:
        decided = [row for row in units if row.outcome in DETERMINATE]
        return TasksCells(
            composite_sr=success_rate([r for r in decided if r.mode == "composite"]),
            primitive_sr=success_rate([r for r in decided if r.mode == "primitive"]),
            gap=sr_gap(decided),
        )

    def axes(self, units: Sequence[JobRow]) -> None:
        return None

    def header(self, table: object) -> list[str]:
        return ["composite SR", "primitive SR", "gap (pp, 95% CI)"]

    def row(self, row: TasksCells, table: object) -> list[str]:
        return [rate_cell(row.composite_sr), rate_cell(row.primitive_sr), gap_cell(row.gap)]

    def section(self, group: RunGroup) -> RunReport:
        return report_of(group.runs, group.warnings)

    def render_section(self, section: RunReport, fmt: ReportFormat, group: RunGroup) -> str:
        if fmt == "md":
            return render_markdown(section)
        plots = report_plots(group.paths, force=True)  # the runs were checked for merging already
        return render_html_body(section) + ("\n" + plots_html(plots) if plots else "")


def success_rate(decided: Sequence[JobRow]) -> Rate | None:
    """Passed / jobs with a verdict; None without any."""
    return Rate(value=sum(r.outcome == "passed" for r in decided) / len(decided), n=len(decided)) if decided else None


def sr_gap(decided: Sequence[JobRow]) -> Gap | None:
    """Composite SR minus primitive SR of one model's decided episode jobs; None unless both modes have some.

    Seeds pair the two modes: with two or more seeds decided in both, the gap is the mean of the per-seed
    gaps with a t interval (seed-to-seed spread is the noise a rerun would show); else the pooled difference.
    """
    composite = [r for r in decided if r.mode == "composite"]
    primitive = [r for r in decided if r.mode == "primitive"]
    if not composite or not primitive:
        return None
    seeds = sorted({r.seed for r in composite} & {r.seed for r in primitive})
    if len(seeds) < 2:
        pooled = _sr(composite) - _sr(primitive)
        return Gap(points=pooled * 100, half_width=None, seeds=len(seeds))
    gaps = [_sr([r for r in composite if r.seed == s]) - _sr([r for r in primitive if r.seed == s]) for s in seeds]
    interval = mean_interval(gaps)
    half = None if interval.half_width is None else interval.half_width * 100
    return Gap(points=interval.mean * 100, half_width=half, seeds=len(seeds))


def gap_cell(gap: Gap | None) -> str:
    if gap is None:
        return MISSING
    text = f"{gap.points:+.1f}"
    if gap.half_width is not None:
        return f"{text} ± {gap.half_width:.1f} ({gap.seeds} seeds)"
    return f"{text} ({gap.seeds} seed{'s' * (gap.seeds != 1)}, no CI)"


def _sr(decided: Sequence[JobRow]) -> float:
    return statistics.fmean(r.outcome == "passed" for r in decided)


DIAGNOSIS = TasksDiagnosis()
