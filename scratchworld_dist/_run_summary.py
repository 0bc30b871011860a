"""What a sweep's run did, apart from ``run_sweep`` itself so that readers of it need not import Ray."""

from __future__ import annotations

from pathlib import Path

from pydantic import BaseModel


class RunSummary(BaseModel):
    """What one ``run_sweep`` call did."""

    run_dir: Path
    planned: int
    already_decided: int
    sent: int
    outcomes: dict[str, int]
    attempts: int
    retried: int
    budget_stop: str | None = None
    """Set when the budget left jobs unstarted."""

    left_out: int = 0
    """Jobs of models the preflight found broken, left out of this run (``--skip-broken-models``)."""
