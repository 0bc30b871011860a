"""The report a set of run directories gets, by the benchmarks they hold.

Runs of one benchmark get its own report, as its kind makes it (the main table with plots in HTML for
episodes, Table 2 for drag, the perception report for perception). Runs of several benchmarks get
the diagnosis table first, then each benchmark's report; runs are merged (and checked for merging) only
with runs of their own benchmark.
"""

from __future__ import annotations

from pathlib import Path

from pydantic import BaseModel

from scratchworld_dist.kinds import job_kind
from scratchworld_dist.reports._diagnosis_report import diagnosis_report, diagnosis_table, render_diagnosis_report
from scratchworld_dist.reports._kind import KindReport
from scratchworld_dist.reports._render import ReportFormat
from scratchworld_dist.reports._run_groups import load_groups, paths_by_benchmark


def report_runs(run_dirs: list[Path], fmt: ReportFormat, *, force: bool = False) -> tuple[str, list[str]]:
    """The report's text in ``fmt`` and its warnings (``RunDirError`` when the runs cannot be read or merged)."""
    paths = paths_by_benchmark(run_dirs)
    if len(paths) > 1:
        return _diagnosis(paths, fmt, force=force)
    benchmark, members = next(iter(paths.items()))
    return job_kind(benchmark, KindReport).report(members, fmt, force=force)


def report_data(run_dirs: list[Path], *, force: bool = False) -> BaseModel:
    """The report as data, the model ``report_runs`` renders: a kind's own report (``RunReport`` for episodes,
    ``DragTable``, ``PerceptionTable``...), or ``DiagnosisReport`` over runs of several kinds."""
    paths = paths_by_benchmark(run_dirs)
    if len(paths) > 1:
        groups = load_groups(paths, force=force)
        return diagnosis_report(groups, diagnosis_table(groups))
    benchmark, members = next(iter(paths.items()))
    return job_kind(benchmark, KindReport).report_data(members, force=force)


def _diagnosis(paths: dict[str, list[Path]], fmt: ReportFormat, *, force: bool) -> tuple[str, list[str]]:
    groups = load_groups(paths, force=force)
    report = diagnosis_report(groups, diagnosis_table(groups))
    return render_diagnosis_report(report, fmt, groups), report.warnings
