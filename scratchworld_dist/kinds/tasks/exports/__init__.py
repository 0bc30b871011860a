"""Exports of task-episode runs for other tools: a leaderboard (CSV and JSON), upstream's submission JSONL,
and ATIF trajectories (Harbor's interchange format, on the ``atif`` package's models)."""

from scratchworld_dist.kinds.tasks.exports._atif import SCHEMA_VERSION as ATIF_VERSION
from scratchworld_dist.kinds.tasks.exports._atif import ImageFiles, atif_trajectory, reasoning_of, trajectory_file_name
from scratchworld_dist.kinds.tasks.exports._export import EXPORT_FORMATS, ExportFormat, ExportSummary, export_runs
from scratchworld_dist.kinds.tasks.exports._leaderboard import LeaderboardEntry, leaderboard, wilson_interval
from scratchworld_dist.kinds.tasks.exports._submission import SubmissionLine

__all__ = [
    "ATIF_VERSION",
    "EXPORT_FORMATS",
    "ExportFormat",
    "ExportSummary",
    "ImageFiles",
    "LeaderboardEntry",
    "SubmissionLine",
    "atif_trajectory",
    "export_runs",
    "leaderboard",
    "reasoning_of",
    "trajectory_file_name",
    "wilson_interval",
]
