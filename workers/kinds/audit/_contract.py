"""The ``audit`` kind's job and detail: one variant of a task's golden project (a mutant or a refactoring),
evaluated by the task's own tests to judge the tests (see ``scratchworld_dist.kinds.audit``)."""

from __future__ import annotations

from typing import Literal

from pydantic import ConfigDict, Field

from workers.contract import JobDetail, JobHeader, ProjectLimits

VariantKind = Literal["golden", "mutant", "refactoring"]
"""The golden itself (its verdict says whether the variants' verdicts measure the grader), or a variant."""


class AuditSpec(JobHeader):
    """One variant as a worker sees it: the project.json to evaluate against its task's payload. No agent acts,
    so it carries no agent, model or seed, and refuses them."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    variant: VariantKind
    project_json: str = Field(repr=False)
    """The variant's project.json; the worker puts it with the assets of its task's golden project."""

    project_limits: ProjectLimits = Field(default_factory=ProjectLimits)

    stop_at_first_failure: bool = False
    """Its tests stop at the first that fails it (a mutant's: ``EvaluationSpec.stop_at_first_failure``)."""


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
