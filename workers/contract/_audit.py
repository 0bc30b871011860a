"""An audit job: one variant of a task's golden project (a mutant or a refactoring), evaluated by the task's
own tests to judge the tests (see ``scratchworld_dist.kinds.audit``)."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, ConfigDict, Field

from workers.contract._detail import JobDetail
from workers.contract._episode import AgentRef
from workers.contract._model import LLMSettings, ModelCacheSettings, ModelSpec
from workers.contract._sb3 import ProjectLimits

VariantKind = Literal["golden", "mutant", "refactoring"]
"""The golden itself (its verdict says whether the variants' verdicts measure the grader), or a variant."""


class AuditSpec(BaseModel):
    """One variant as a worker sees it: the project.json to evaluate against its task's payload (no agent acts)."""

    model_config = ConfigDict(frozen=True)

    job_id: str
    attempt: int = Field(ge=1)
    task_id: str
    variant: VariantKind
    project_json: str = Field(repr=False)
    """The variant's project.json; the worker puts it with the assets of its task's golden project."""

    timeout_s: float = Field(gt=0)
    project_limits: ProjectLimits = Field(default_factory=ProjectLimits)
    harness: str | None = None
    agent: AgentRef | None = None
    agent_code: str | None = None
    model: ModelSpec | None = None
    seed: int = 0
    llm: LLMSettings | None = None
    model_cache: ModelCacheSettings | None = None


class AuditObservation(JobDetail):
    """What a user could observe of a variant the tests misjudged (a surviving mutant, a failed refactoring):
    its run and the golden's, traced under the same seed and inputs, compared frame by frame."""

    kind: str = "audit"
    observed: Literal["equivalent", "differs"]
    """``equivalent``: the two traces are the same; ``differs``: ``difference`` says where first."""

    difference: str | None = None
    """The first observable difference, as one line (``frame 12, Cat, bubble: ... vs ...``)."""

    truncated: bool = False
    """A trace reached its size cap: they were compared only as far as both were recorded."""
