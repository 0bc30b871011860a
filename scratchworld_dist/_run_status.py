"""How far a run got, read from its files alone: ``scratchworld status`` prints it, ``status --json`` dumps it."""

from __future__ import annotations

from collections import Counter
from datetime import datetime
from pathlib import Path

from pydantic import BaseModel

from scratchworld_dist.results import RunManifest, RunStore, effective_rows
from scratchworld_dist.sweep import SuiteInfo


class SessionStatus(BaseModel):
    """One ``run`` of the directory."""

    started_at: datetime
    finished_at: datetime | None
    """None: it did not finish (still running, or stopped without a word)."""

    host: str
    pid: int
    planned: int
    """Jobs it set out to run."""

    budget_stop: str | None


class RunStatus(BaseModel):
    """A run directory's progress (``status --json``)."""

    run_name: str
    run_dir: Path
    suite: SuiteInfo
    harness: str | None
    tags: dict[str, str]
    planned_jobs: int
    decided: int
    passed: int
    failed: int
    error: int
    not_yet_run: int
    attempts: int
    """Attempts recorded (retries included) of the run as it stands."""

    errors: dict[str, int]
    """Jobs left in error, by error class, most frequent first."""

    cost_usd: float
    """Spend of every recorded attempt."""

    sessions: list[SessionStatus]


def run_status(run_dir: Path, manifest: RunManifest) -> RunStatus:
    """``run_dir``'s progress, from its manifest and its rows."""
    rows = manifest.current_rows(RunStore(run_dir).job_rows())
    effective = list(effective_rows(rows))
    outcomes = Counter(r.outcome for r in effective)
    errors = Counter(r.error_class or "?" for r in effective if r.outcome == "error")
    return RunStatus(
        run_name=manifest.run_name,
        run_dir=run_dir,
        suite=manifest.suite,
        harness=manifest.harness.digest if manifest.harness else None,
        tags=manifest.tags,
        planned_jobs=manifest.planned_jobs,
        decided=outcomes["passed"] + outcomes["failed"],
        passed=outcomes["passed"],
        failed=outcomes["failed"],
        error=outcomes["error"],
        not_yet_run=max(manifest.planned_jobs - len(effective), 0),
        attempts=len(rows),
        errors=dict(errors.most_common()),
        cost_usd=sum(r.cost_usd for r in rows),
        sessions=[
            SessionStatus(
                started_at=s.started_at, finished_at=s.finished_at, host=s.host, pid=s.pid, planned=s.planned,
                budget_stop=s.budget_stop,
            )
            for s in manifest.sessions
        ],
    )  # fmt: skip
