"""A regrade job: a project an agent already left, evaluated again under other conditions.

No agent runs: the worker loads ``project`` into one of its clean evaluation editors and runs the
evaluation spec of the task payload it is sent with (which names the profile and the clock).
"""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field

from workers.contract._sb3 import ProjectLimits


class RegradeSpec(BaseModel):
    """One regrade as a worker sees it: which stored project to evaluate against which task."""

    model_config = ConfigDict(frozen=True)

    job_id: str
    attempt: int = Field(ge=1)
    task_id: str
    project: bytes = Field(repr=False)
    """The final project the source attempt stored (``final.sb3``)."""

    timeout_s: float = Field(gt=0)
    """Wall-clock limit for the evaluation, editor included."""

    project_limits: ProjectLimits = Field(default_factory=ProjectLimits)
    harness: str | None = None
    """The harness fingerprint the driver planned the regrade under; a worker running other code refuses it."""
