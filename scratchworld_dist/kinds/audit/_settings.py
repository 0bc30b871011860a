"""The audit kind's section of a sweep config, ``audit:``: how many variants of each golden, from which seed."""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field


class AuditSweep(BaseModel):
    """Which mutants and refactorings of each task's golden project are evaluated."""

    model_config = ConfigDict(extra="forbid")

    mutants_per_task: int | None = Field(default=None, gt=0)
    """At most this many mutants per task, spread over the operators (None: every one)."""

    refactorings_per_task: int | None = Field(default=None, ge=0)
    """At most this many refactorings per task (None: every one; 0: none)."""

    seed: int = 0
    """Which mutants and refactorings a cap picks (the same seed picks the same ones)."""
