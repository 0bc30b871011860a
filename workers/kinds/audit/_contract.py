"""The ``audit`` kind's job and details: one variant of a task's golden project (a mutant or a refactoring),
evaluated by the task's own tests to judge the tests (see ``scratchworld_dist.kinds.audit``)."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, JsonValue

from workers.contract import JobDetail, JobHeader, ProjectLimits
from workers.kinds.audit._exploration import ExplorationPlan

VariantKind = Literal["golden", "mutant", "refactoring"]
"""The golden itself (its verdict says whether the variants' verdicts measure the grader), or a variant."""

Observed = Literal["equivalent", "differs", "outside_task"]
"""What the traces showed of a misjudged variant: the golden's behaviour in every run, a difference in a run the
task allows, or differences only under answers its instruction rules out."""

Vacuity = Literal["never_starts", "observes_nothing"]
"""Why a grader judges nothing: its tests never start the program, or read nothing the program changes."""


class AuditSpec(JobHeader):
    """One variant as a worker sees it: the project.json to evaluate against its task's payload. No agent acts,
    so it carries no agent, model or seed, and refuses them."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    variant: VariantKind
    project_json: str = Field(repr=False)
    """The variant's project.json; the worker puts it with the assets of its task's golden project."""

    project_limits: ProjectLimits = Field(default_factory=ProjectLimits)

    exploration: ExplorationPlan | None = None
    """The task's exploration (None: the tests' own run alone decides equivalence, as before explorations)."""

    stop_at_first_failure: bool = False
    """Its tests stop at the first that fails it (a mutant's: ``EvaluationSpec.stop_at_first_failure``)."""


class ShownBy(BaseModel):
    """The run in which a difference showed, and what had been done to the program by then."""

    model_config = ConfigDict(frozen=True)

    run: str
    """``tests`` (the task's own tests, seed 0) or the exploration episode's name."""

    seed: int
    answers: list[str] = Field(default_factory=list)
    """The answers given in that run (the golden's and the variant's, in order, without repeats)."""

    stimulus: str | None = None
    """The last stimulus done before the difference's frame (``key 'space' at 2.0 s``); None: none yet, or a
    tests' run (the tests drive it)."""

    def describe(self) -> str:
        """``exploration 'seed 2, answers: task numbers' (answers '3', '4'), after key 'space' at 2.0 s``."""
        where = "the tests' own run" if self.run == "tests" else f"exploration {self.run!r}"
        given = f" (answers {', '.join(repr(a) for a in self.answers)})" if self.answers else ""
        after = f", after {self.stimulus}" if self.stimulus else ""
        return f"{where}{given}{after}"


class AuditObservation(JobDetail):
    """What a user could observe of a variant the tests misjudged (a surviving mutant, a failed refactoring):
    its runs and the golden's (the tests' own, then the task's exploration), traced under the same seeds and
    inputs, compared frame by frame."""

    kind: str = "audit"
    observed: Observed
    """``equivalent``: every run's traces are the same; ``differs``: ``difference`` says where first;
    ``outside_task``: only runs with answers the instruction rules out differ (``difference`` the first)."""

    difference: str | None = None
    """The first observable difference, as one line (``frame 12, Cat, bubble: ... vs ...``)."""

    shown_by: ShownBy | None = None
    """The run that showed ``difference``."""

    first: dict[str, JsonValue] | None = None
    """``difference`` as data: frame, target, field, a, b, variable (``workers.evaluation.TraceDifference``)."""

    runs: int = 0
    """Runs whose traces were compared (the tests' own, then episodes until a difference the task allows)."""

    truncated: bool = False
    """A trace reached its size cap: they were compared only as far as both were recorded."""


class GraderCheck(JobDetail):
    """What the golden's job found of its task's tests: whether they start the program and read anything the
    program does (``vacuous`` when they do not), from the tests' own run and the golden's exploration."""

    kind: str = "audit"
    started: bool
    threads: int = 0
    """Scripts the tests started (the flag, keys, clicks and broadcasts they sent)."""

    reads: list[tuple[str, str]] = Field(default_factory=list)
    """(target, field) the tests read (``*``: any target)."""

    changes: list[tuple[str, str]] = Field(default_factory=list)
    """(target, field) the golden's exploration changed (clones fold into their sprite)."""

    vacuous: Vacuity | None = None
    """``never_starts`` or ``observes_nothing``; None: the tests start it and read something it changes."""
