"""A leaderboard of task-episode runs: one entry per agent, model and mode, ranked by success rate within its
mode (composite and primitive are different tasks for an agent, so each mode is its own ranking).

Each entry is the episode report's row (effective attempts, errors left out of SR and PSR) with a 95%
Wilson score interval on SR, the interval for a proportion that stays inside [0, 1] and behaves at 0 and
100% (SciPy's ``binomtest``). Entries rank by SR, then PSR, then cost per success; entries equal in all three
share a rank, and the next rank counts them (competition ranking: 1, 1, 3).
"""

from __future__ import annotations

import csv
import io
import json
from collections.abc import Sequence
from itertools import groupby
from pathlib import Path

from pydantic import BaseModel

from scratchworld_dist.kinds.tasks.report import ReportRow, RunReport, build_report


class LeaderboardEntry(BaseModel):
    rank: int
    """Within its mode; entries tied in SR, PSR and cost per success share it (1, 1, 3)."""

    label: str
    agent: str
    model: str
    mode: str
    jobs: int
    determinate: int
    passed: int
    sr: float | None
    sr_low: float | None
    """Lower end of the 95% Wilson interval on SR."""

    sr_high: float | None
    psr: float | None
    coverage: float | None
    input_tokens: int
    output_tokens: int
    cost_usd: float
    cost_per_success: float | None


def wilson_interval(passed: int, determinate: int) -> tuple[float | None, float | None]:
    """The 95% Wilson score interval of ``passed / determinate`` (None without a verdict)."""
    if determinate == 0:
        return None, None
    from scipy.stats import binomtest  # SciPy's import takes most of a second: paid by the leaderboard

    interval = binomtest(passed, determinate).proportion_ci(confidence_level=0.95, method="wilson")
    return float(interval.low), float(interval.high)


def leaderboard(report: RunReport) -> list[LeaderboardEntry]:
    """The report's rows ranked within each mode (modes in the report's order): SR first (no verdict last), then
    PSR, then the cheaper success; rows equal in all three share a rank."""

    def order(row: ReportRow) -> tuple[float, float, float]:
        cost = row.cost_per_success if row.cost_per_success is not None else float("inf")
        return (-(row.sr if row.sr is not None else -1.0), -(row.psr or 0.0), cost)

    modes = list(dict.fromkeys(row.mode for row in report.rows))
    ranked: list[tuple[int, ReportRow]] = []
    for mode in modes:
        rows = sorted((row for row in report.rows if row.mode == mode), key=order)
        position = 1
        for _, tied in groupby(rows, key=order):
            group = list(tied)
            ranked += [(position, row) for row in group]
            position += len(group)
    entries = []
    for rank, row in ranked:
        low, high = wilson_interval(row.passed, row.determinate)
        entries.append(
            LeaderboardEntry(
                rank=rank, label=row.label, agent=row.agent, model=row.model, mode=row.mode, jobs=row.jobs,
                determinate=row.determinate, passed=row.passed, sr=row.sr, sr_low=low, sr_high=high, psr=row.psr,
                coverage=row.coverage, input_tokens=row.input_tokens, output_tokens=row.output_tokens,
                cost_usd=row.cost_usd, cost_per_success=row.cost_per_success,
            )
        )  # fmt: skip
    return entries


def leaderboard_csv(entries: list[LeaderboardEntry]) -> str:
    """The entries as CSV with a header row (empty cells for values that do not exist)."""
    out = io.StringIO()
    writer = csv.DictWriter(out, fieldnames=list(LeaderboardEntry.model_fields), lineterminator="\n")
    writer.writeheader()
    for entry in entries:
        writer.writerow({k: "" if v is None else v for k, v in entry.model_dump().items()})
    return out.getvalue()


def leaderboard_files(run_dirs: Sequence[Path], *, force: bool = False) -> tuple[dict[str, bytes], list[str]]:
    """``leaderboard.csv`` and ``leaderboard.json`` of the runs (name: content), and the report's warnings."""
    report = build_report(list(run_dirs), force=force)
    entries = leaderboard(report)
    table = {"runs": [run.model_dump(mode="json") for run in report.runs], "entries": [e.model_dump() for e in entries]}
    files = {
        "leaderboard.csv": leaderboard_csv(entries).encode(),
        "leaderboard.json": (json.dumps(table, indent=2) + "\n").encode(),
    }
    return files, report.warnings
