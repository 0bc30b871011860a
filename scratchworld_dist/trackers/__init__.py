"""Experiment trackers (the config's ``loggers:``): MLflow and Weights & Biases, each an optional extra.

A run reports its parameters, its metrics as jobs finish (``RunTally``, from the events ``events.jsonl`` holds) and
its report and leaderboard at the end, through ``TrackerFeed`` (a thread per tracker: the scheduler never waits on
one, and one that fails is said once and left out). The tracker runs are recorded in the manifest
(``TrackerRuns``), so a resumed run continues them.
"""

from __future__ import annotations

import secrets
from collections.abc import Callable
from pathlib import Path

from scratchworld_dist.results import RunManifest, TrackerRuns, read_events
from scratchworld_dist.sweep import RunPlan
from scratchworld_dist.trackers._artifacts import run_files
from scratchworld_dist.trackers._feed import Artifacts, TrackerFeed
from scratchworld_dist.trackers._params import planned_jobs, run_info
from scratchworld_dist.trackers._registry import TRACKERS, configured_trackers
from scratchworld_dist.trackers._tally import PlannedJob, RunTally
from scratchworld_dist.trackers._tracker import RunInfo, Tracker, redacted


def start_trackers(
    plan: RunPlan, manifest: RunManifest, run_dir: Path, say: Callable[[str], None]
) -> TrackerFeed | None:
    """The feed of the trackers ``plan``'s config configures (None: it configures none), each continuing the run
    recorded in ``manifest`` (given a key there now, on the run's first session with a tracker), its metrics going
    on from the events ``run_dir`` holds; ``ConfigError`` when a tracker's package is not installed."""
    trackers = configured_trackers(plan.config.loggers)
    if not trackers:
        return None
    if manifest.trackers is None:
        manifest.trackers = TrackerRuns(key=secrets.token_hex(8))
    info = run_info(plan, manifest, manifest.trackers.key, dict(manifest.trackers.runs))
    return TrackerFeed(trackers, info, planned_jobs(plan), read_events(run_dir), plan.config.loggers, say)


__all__ = [
    "TRACKERS",
    "Artifacts",
    "PlannedJob",
    "RunInfo",
    "RunTally",
    "Tracker",
    "TrackerFeed",
    "configured_trackers",
    "redacted",
    "run_files",
    "start_trackers",
]
