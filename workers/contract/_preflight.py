"""What the preflight found about each model a sweep calls, before any editor opened.

Recorded with the session in the run's manifest (never part of a job's identity), and returned from the
node that checked them on a cluster. No field ever holds a key: causes are scrubbed like model-call errors.
"""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field

from workers.contract._errors import ModelErrorClass


class ModelCheck(BaseModel):
    """One model: whether its settings resolve and, when probed, what its one smallest call said and cost."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    name: str
    """The model's label (reports and the terminal name it so)."""

    model: str
    """The LiteLLM model string."""

    probed: bool = False
    """Whether a call was made (False: only its key and base URL were checked, or they were broken)."""

    error_class: ModelErrorClass | None = None
    """Why the model cannot be called (None: it can)."""

    cause: str | None = None
    """The reason on one line (the variable not set, the provider's answer...)."""

    attempts: int = 0
    input_tokens: int = 0
    output_tokens: int = 0
    cost_usd: float = 0.0
    """LiteLLM's price of the probe (0.0 for a model it has no price for, or when nothing answered)."""

    latency_s: float | None = None
    """Duration of the probe's successful HTTP attempt."""

    @property
    def broken(self) -> bool:
        return self.error_class is not None


class Preflight(BaseModel):
    """The preflight of one session: the models its jobs call, checked (and probed) before any job started."""

    model_config = ConfigDict(extra="forbid")

    probe: bool
    """Whether each model was called once (else only its key and base URL were checked)."""

    where: str
    """Where the checks ran: ``driver``, or the cluster node whose environment the workers share."""

    models: list[ModelCheck] = Field(default_factory=list)
    left_out_jobs: int = 0
    """Jobs of broken models this session did not run (``--skip-broken-models``); a later run plans them."""

    @property
    def cost_usd(self) -> float:
        return sum(check.cost_usd for check in self.models)

    @property
    def broken(self) -> list[ModelCheck]:
        return [check for check in self.models if check.broken]
