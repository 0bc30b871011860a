"""The report a set of run directories gets, by the benchmarks they hold.

Runs of one benchmark get its own report: the main table (with plots in HTML) for episodes, Table 2 for
the drag benchmark, the perception report for the perception benchmark. Runs of several benchmarks get
the diagnosis table first, then each benchmark's report; runs are merged (and checked for merging) only
with runs of their own benchmark.
"""

from __future__ import annotations

from pathlib import Path

from scratchworld_dist.kinds import job_kind
from scratchworld_dist.reports._build import report_of
from scratchworld_dist.reports._diagnosis import diagnosis_table
from scratchworld_dist.reports._diagnosis_report import DiagnosisReport, render_diagnosis_report
from scratchworld_dist.reports._drag_table import drag_table_of
from scratchworld_dist.reports._perception_table import (
    perception_table_of,
)
from scratchworld_dist.reports._plots import report_plots
from scratchworld_dist.reports._render import ReportFormat
from scratchworld_dist.reports._run_groups import load_groups, paths_by_benchmark


def report_runs(run_dirs: list[Path], fmt: ReportFormat, *, force: bool = False) -> tuple[str, list[str]]:
    """The report's text in ``fmt`` and its warnings (``RunDirError`` when the runs cannot be read or merged)."""
    paths = paths_by_benchmark(run_dirs)
    if len(paths) > 1:
        return _diagnosis(paths, fmt, force=force)
    benchmark, members = next(iter(paths.items()))
    return job_kind(benchmark).report(members, fmt, force=force)


def _diagnosis(paths: dict[str, list[Path]], fmt: ReportFormat, *, force: bool) -> tuple[str, list[str]]:
    groups = {group.benchmark: group for group in load_groups(paths, force=force)}
    episodes, drag, perception = groups.get("tasks"), groups.get("drag"), groups.get("perception")
    report = DiagnosisReport(
        diagnosis=diagnosis_table(list(groups.values())),
        episodes=None if episodes is None else report_of(episodes.runs, episodes.warnings),
        drag=None if drag is None else drag_table_of(drag.runs, drag.warnings, drag.tables["drags"]),  # type: ignore[arg-type]
        perception=None
        if perception is None
        else perception_table_of(perception.runs, perception.warnings, perception.tables["perception"]),  # type: ignore[arg-type]
    )
    plots = report_plots(episodes.paths, force=force) if fmt == "html" and episodes is not None else []
    return render_diagnosis_report(report, fmt, plots), report.warnings
