"""The report a set of run directories gets: the drag benchmark's Table 2 for drag runs, else the main table
(with plots in HTML)."""

from __future__ import annotations

from pathlib import Path

from scratchworld_dist.reports._build import build_report
from scratchworld_dist.reports._drag_table import build_drag_report, is_drag_run, render_drag
from scratchworld_dist.reports._plots import report_plots
from scratchworld_dist.reports._render import ReportFormat, render


def report_runs(run_dirs: list[Path], fmt: ReportFormat, *, force: bool = False) -> tuple[str, list[str]]:
    """The report's text in ``fmt`` and its warnings (``RunDirError`` when the runs cannot be read or merged)."""
    if any(is_drag_run(path) for path in run_dirs):
        drag = build_drag_report(run_dirs, force=force)
        return render_drag(drag, fmt), drag.warnings
    report = build_report(run_dirs, force=force)
    plots = report_plots(run_dirs, force=force) if fmt == "html" else []  # drawing is slow: only for a page
    return render(report, fmt, plots), report.warnings
