"""The files a run hands its trackers at its end: its report (Markdown and JSON) and its kind's own (a leaderboard)."""

from __future__ import annotations

from pathlib import Path

from scratchworld_dist.kinds import job_kind
from scratchworld_dist.reports import KindReport, report_runs


def run_files(run_dir: Path, benchmark: str) -> dict[str, bytes]:
    """``report.md``, ``report.json`` and the kind's ``tracker_files`` of the run as it stands (name: content)."""
    files = {f"report.{fmt}": report_runs([run_dir], fmt)[0].encode() for fmt in ("md", "json")}
    return {**files, **job_kind(benchmark, KindReport).tracker_files(run_dir)}
