"""Browserless stand-ins for episodes, as a sweep configures them (run by ``workers.kinds.tasks``).

Part of a job's identity: a synthetic verdict must never be taken for a real one.
"""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field, NonNegativeFloat


class SyntheticEpisodes(BaseModel):
    """How synthetic episodes behave."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    duration_s: float = Field(default=0.0, ge=0)
    """How long each episode takes."""

    startup_s: float = Field(default=0.0, ge=0)
    """How long a worker takes to start, and to restart after it died (a browser worker's imports
    and launch take seconds on a busy node)."""

    warm_s: list[NonNegativeFloat] = Field(default_factory=list)
    """How long worker ``i`` takes to open its editors ahead of its first job (``warm_s[i]``; none past the
    list's end): workers of one node that finish at different times. Not part of a job's identity."""

    fail_tasks: list[str] = Field(default_factory=list)
    """Task ids whose episodes fail one of their two tests; every other task passes."""

    tasks: list[str] | None = None
    """Task ids that run as synthetic episodes; the others run for real. None: every task."""

    def covers(self, task_id: str) -> bool:
        """Whether the jobs of ``task_id`` are synthetic."""
        return self.tasks is None or task_id in self.tasks
