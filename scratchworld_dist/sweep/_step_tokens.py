"""How many tokens a job's model calls take, as ``plan`` estimates spend before a run: tokens per step (one model
call), steps per attempt and attempts per job, measured in earlier runs or a kind's documented default."""

from __future__ import annotations

from pydantic import BaseModel, Field


class TokenRates(BaseModel):
    """Tokens one job of a line (model, agent, mode) takes, and where the figures come from."""

    input_per_step: float = Field(ge=0)
    output_per_step: float = Field(ge=0)
    steps_per_attempt: float | None = Field(default=None, ge=0)
    """Measured steps per attempt; None: ``budget_share`` of the job's step budget."""

    budget_share: float = Field(default=0.5, gt=0, le=1)
    """Share of the step budget an attempt is taken to use when no run measured it."""

    attempts_per_job: float = Field(default=1.0, ge=1)
    """Attempts per job (retries cost too): measured, else 1."""

    source: str
    """Where the figures come from: ``default (...)`` or the runs and attempts they were measured in."""

    def steps(self, budget: int) -> float:
        """Steps one attempt takes under a step budget of ``budget``."""
        if self.steps_per_attempt is not None:
            return min(self.steps_per_attempt, float(budget))
        return budget * self.budget_share


DEFAULT_RATES = TokenRates(
    input_per_step=2_000, output_per_step=200, budget_share=1.0, source="default: one answer per item"
)
"""A single-step kind's job without measurements (a screenshot of about 1,100 tokens, a prompt and its question;
the answer with its reasoning)."""
