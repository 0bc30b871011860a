"""What an evaluation produces: per-test verdicts, counts, timings, or a classified error."""

from __future__ import annotations

import re
from typing import Literal

from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    JsonValue,
    SerializerFunctionWrapHandler,
    field_validator,
    model_serializer,
)

from workers.contract._evaluation_spec import (
    EvaluationClock,
    EvaluationPage,
    EvaluationProfile,
    EvaluationRender,
    drop_unset_perturbation,
)
from workers.contract._frame_timing import FrameLateness, RecordedTiming
from workers.contract._perturbation import EvaluationPerturbation

EvalErrorKind = Literal[
    "project_invalid",  # the project is not a loadable .sb3 (corrupt zip, bad project.json)
    "project_too_large",  # the project is over the size limits (checked before the browser sees it)
    "script_invalid",  # the evaluation script or helper does not parse or exports no function
    "script_error",  # the script threw or rejected while testing the project
    "script_timeout",  # the script exceeded its hard timeout (hung or too slow) and was killed
    "result_invalid",  # the script returned something that is not a test report
    "editor_failure",  # the browser or editor broke: infrastructure, not the project's fault
]

MAX_MESSAGE = 2000
"""The longest error message kept (the cause fits; a script that throws a megabyte does not)."""

_CONTROL = re.compile(r"[\x00-\x1f\x7f]")

VERDICT_ERROR_KINDS: frozenset[EvalErrorKind] = frozenset({"script_error", "script_timeout"})
"""Errors that upstream ScratchWorld scores as a failed project (PSR 0) rather than dropping."""


class ProfileConditions(BaseModel):
    """What the page looked like when the script ran."""

    model_config = ConfigDict(frozen=True)

    profile: EvaluationProfile
    stage_canvas: tuple[int, int]
    device_pixel_ratio: float
    mouse_known: bool
    """Whether the VM had a mouse position before the project loaded."""

    clock: EvaluationClock = "real"
    """The clock the script ran on (virtual: simulated time, capped at the spec's timeout)."""

    render: EvaluationRender = "every_frame"
    """When the stage was drawn (results made before ``on_demand`` existed drew every frame)."""

    page: EvaluationPage = "editor"
    """The page the script ran in (results made before the bare page existed ran in the editor)."""

    timing: RecordedTiming | None = None
    """How the VM's frames were timed: ``real`` on the real clock, else the virtual model (None: recorded
    before timing was, when virtual frames were always ``ideal``)."""

    frame_lateness: FrameLateness | None = None
    """The coefficients of ``calibrated`` timing."""

    perturbation: EvaluationPerturbation | None = None
    """What ``scratchworld flakes`` varied for this run (left out of the dump when None, as results were)."""

    @model_serializer(mode="wrap")
    def _without_default_perturbation(self, handler: SerializerFunctionWrapHandler) -> dict[str, object]:
        return drop_unset_perturbation(handler(self), self.perturbation)


class EvalError(BaseModel):
    """Why an evaluation produced no regular test report."""

    model_config = ConfigDict(frozen=True)

    kind: EvalErrorKind
    """Stable class of the failure."""

    message: str
    """Human-readable cause, naming the script or file involved: one line of at most ``MAX_MESSAGE`` characters."""

    @field_validator("message")
    @classmethod
    def _one_line(cls, message: str) -> str:
        """Scripts and projects write these words (a thrown error, the VM's complaint): line breaks and
        control characters would forge lines in logs and terminals, and a megabyte would bloat every row."""
        line = " ".join(_CONTROL.sub(" ", message).split())
        return line if len(line) <= MAX_MESSAGE else line[: MAX_MESSAGE - 1] + "…"


class TestVerdict(BaseModel):
    """One unit test of an evaluation script."""

    __test__ = False  # not a pytest test class, despite the name

    name: str
    """The test's name as the script reports it."""

    passed: bool
    """Whether the test passed."""

    error: str | None = None
    """The script's own error text for this test, if any."""

    duration_ms: float | None = None
    """How long the script says the test took."""

    timed_out: bool | None = None
    """Whether the script says the test hit its own timeout."""

    meta: JsonValue = None
    """Anything else the script attached to the test, kept as JSON."""


class EvalTimings(BaseModel):
    """Wall-clock seconds spent in each phase."""

    editor_ready_s: float | None = None
    """Fresh editor page until ready (None when a recycled editor was reused)."""

    project_load_s: float | None = None
    """Loading the project into the VM."""

    script_s: float | None = None
    """Running the evaluation script."""

    script_clock_s: float | None = None
    """The script's run on the page's clock: simulated seconds under the virtual clock."""

    total_s: float = 0.0
    """Everything, from request to result."""


class EarlyStop(BaseModel):
    """An evaluation that ran no test after the first that failed (``EvaluationSpec.stop_at_first_failure``)."""

    model_config = ConfigDict(frozen=True)

    test: str
    """The first test that failed: the one that decided the verdict."""

    not_run: int = Field(ge=1)
    """The script's tests after it, not run: counted in ``total`` as not passed, left out of ``tests``."""


class EvalResult(BaseModel):
    """The verdict on one project for one task, exactly as the benchmark scores it.

    ``success`` is all tests passed; ``psr`` is the fraction of tests passed. With an ``error``
    the counts are zero and no test list exists.
    """

    success: bool
    """All tests passed (and there was at least one)."""

    passed: int = Field(ge=0)
    """Number of tests passed."""

    total: int = Field(ge=0)
    """Number of tests run."""

    psr: float = Field(ge=0.0, le=1.0)
    """Partial success rate: passed / total (0 when total is 0)."""

    tests: list[TestVerdict] = Field(default_factory=list)
    """Per-test verdicts in the order the script reported them."""

    error: EvalError | None = None
    """Set when no regular report could be produced."""

    warnings: list[str] = Field(default_factory=list)
    """Oddities that did not prevent a verdict (e.g. counts that disagree with details)."""

    console: list[str] = Field(default_factory=list)
    """Console output of the page during the evaluation (bounded)."""

    timings: EvalTimings = Field(default_factory=EvalTimings)
    """Where the time went."""

    conditions: ProfileConditions | None = None
    """The evaluation profile and the page conditions it was checked to have (None if it never got there)."""

    stopped_early: EarlyStop | None = None
    """Set when the script's tests stopped at the first that failed, with tests left to run."""

    @property
    def random_seed(self) -> int | None:
        """The seed the run drew ``Math.random`` from (None: no run, or an unseeded one)."""
        perturbation = self.conditions.perturbation if self.conditions is not None else None
        return perturbation.random_seed if perturbation is not None else None

    @classmethod
    def failure(
        cls, kind: EvalErrorKind, message: str, *, console: list[str] | None = None, timings: EvalTimings | None = None
    ) -> EvalResult:
        """A result that carries an error and no test report."""
        return cls(
            success=False,
            passed=0,
            total=0,
            psr=0.0,
            error=EvalError(kind=kind, message=message),
            console=console or [],
            timings=timings or EvalTimings(),
        )
