"""What an evaluation needs besides the project, as data that can cross processes."""

from __future__ import annotations

import re
from typing import Literal

from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    JsonValue,
    SerializerFunctionWrapHandler,
    model_serializer,
    model_validator,
)

from workers.contract._frame_timing import EvaluationTiming, FrameLateness
from workers.contract._perturbation import EvaluationPerturbation

EvaluationClock = Literal["virtual", "real"]
"""The page clock an evaluation script runs on: simulated time skipping ahead, or the wall clock."""

EvaluationProfile = Literal["native", "upstream"]
"""The page conditions of an evaluation (see ``workers.evaluation._profiles``)."""

EvaluationPage = Literal["bare", "editor"]
"""The page an evaluation runs in: the VM, renderer and audio engine alone (``scratch-gui/bare.html``),
or the whole Scratch editor (``index.html``), the reference."""

EvaluationRender = Literal["on_demand", "every_frame"]
"""When the stage is drawn during an evaluation: only when something reads the picture (a snapshot,
the canvas's own image), or on every VM frame as in an editor someone watches."""


class EvaluationSpec(BaseModel):
    """Everything besides the project that an evaluation needs, as data that can cross processes."""

    model_config = ConfigDict(frozen=True)

    script_name: str
    """File name of the evaluation script, used in messages and stack traces."""

    script_source: str
    """CommonJS module source whose ``module.exports`` is ``async (vm, config, cleanup) => result``."""

    helper_name: str | None = None
    """File name of the suite's helper module, if any."""

    helper_source: str | None = None
    """Helper module source, installed as a global before the script loads."""

    helper_global: str = "EvaluationUtils"
    """Global name the helper's exports are published under (upstream: ``EvaluationUtils``)."""

    timeout_s: float = Field(gt=0)
    """Hard limit for the script, in simulated seconds under the virtual clock; past it: ``script_timeout``."""

    profile: EvaluationProfile = "native"
    """Page conditions of the evaluation; part of a job's identity."""

    clock: EvaluationClock = "real"
    """Clock of the script's run (see ``scratch-gui/clock.js``); part of a job's identity like the profile."""

    render: EvaluationRender = "on_demand"
    """When the stage is drawn (see ``scratch-gui/bridge.js``, ``drawOnDemand``); part of a job's identity.
    Touching, colour sensing and the pen do not read the drawn stage, so skipping the frames nobody
    looks at halves an evaluation's work without changing what a script sees."""

    page: EvaluationPage = "bare"
    """The page the script runs in; part of a job's identity. The bare page gives the verdicts of the editor
    page (README, "Evaluation page") for less CPU; a script that needs the editor runs there whatever is asked
    (``editor_need``)."""

    timing: EvaluationTiming = "ideal"
    """How the VM's frames are timed in virtual time (``workers.contract._frame_timing``); part of a
    job's identity, left out of the dump when ``ideal`` (today's exact timing) so that job ids stay as they were."""

    frame_lateness: FrameLateness | None = None
    """The coefficients of ``calibrated`` timing (None otherwise): a re-calibration changes job identity."""

    config: dict[str, JsonValue] = Field(default_factory=dict)
    """Second argument handed to the script (upstream always passes ``{}``)."""

    perturbation: EvaluationPerturbation | None = None
    """Conditions varied on purpose by ``scratchworld flakes`` (seeded randomness, frame phase, mouse,
    timer lateness); None, the default, is left out of the dump so that job ids stay as they were."""

    stop_at_first_failure: bool = False
    """Run no test after the first one that fails (``scratch-gui/evaluation/first-failure.js``): the verdict
    "failed" is then decided, so a grader audit's mutant needs no more (``EvalResult.stopped_early``). Only the
    audit asks for it; False, the default, is left out of the dump so that job ids stay as they were."""

    @model_validator(mode="before")
    @classmethod
    def _editor_for_a_script_that_needs_it(cls, data: object) -> object:
        """A script that names the editor's DOM or blocks runs in the editor page (``_evaluation_page``)."""
        if not isinstance(data, dict) or data.get("page", "bare") != "bare":
            return data
        needs = editor_need(data.get("script_source"), data.get("helper_source")) is not None
        return {**data, "page": "editor"} if needs else data

    @model_validator(mode="after")
    def _timing_needs_virtual_time(self) -> EvaluationSpec:
        """The real clock has its own phase and lateness, which nothing here controls."""
        perturbation = self.perturbation
        if perturbation is not None and self.clock != "virtual":
            if perturbation.lateness is not None and perturbation.lateness.ms > 0:
                raise ValueError("timer lateness is a perturbation of the virtual clock only")
            if perturbation.phase_ms > 0:
                raise ValueError("the frame phase is a perturbation of the virtual clock only")
        return self

    @model_validator(mode="after")
    def _calibrated_timing_has_its_model(self) -> EvaluationSpec:
        if self.timing == "calibrated":
            if self.clock != "virtual":
                raise ValueError("calibrated frame timing is a model of the virtual clock (the real clock has its own)")
            if self.frame_lateness is None:
                raise ValueError("calibrated frame timing needs its frame_lateness coefficients")
        elif self.frame_lateness is not None:
            raise ValueError(f"frame_lateness is only used by calibrated frame timing, not {self.timing}")
        return self

    @model_serializer(mode="wrap")
    def _without_default_perturbation(self, handler: SerializerFunctionWrapHandler) -> dict[str, object]:
        dumped = drop_unset_timing(handler(self), self.timing)
        if not self.stop_at_first_failure:
            dumped.pop("stop_at_first_failure", None)
        return drop_unset_perturbation(dumped, self.perturbation)


def drop_unset_timing(dumped: dict[str, object], timing: str | None) -> dict[str, object]:
    """``dumped`` without ``timing`` and ``frame_lateness`` under ``ideal`` timing, as before timing existed."""
    if timing in ("ideal", None):
        dumped.pop("timing", None)
        dumped.pop("frame_lateness", None)
    return dumped


def drop_unset_perturbation(
    dumped: dict[str, object], perturbation: EvaluationPerturbation | None
) -> dict[str, object]:
    """``dumped`` without its ``perturbation`` key when there is none: models that gained the field dump as before."""
    if perturbation is None:
        dumped.pop("perturbation", None)
    return dumped


# Whether an evaluation script needs the editor page, or the bare evaluation page serves it. The bare page
# (``scratch-gui/bare.html``) has the VM, the renderer and the audio engine, and no editor GUI. A script that
# reaches for the editor's DOM or its block editor cannot run there, and is detected from its source (and its
# helper's) before any page opens: a mention of ``document``, ``ScratchBlocks`` or ``Blockly``, a DOM query or
# React's internals sends its evaluations to the editor page. None of our tasks and none of upstream's mention any.
_GUI_NAMES = re.compile(
    r"\b(document|ScratchBlocks|Blockly|querySelector(?:All)?|getElementsBy\w+|getElementById|__reactFiber\w*|ReactDOM)\b"
)


def editor_need(*sources: str | None) -> str | None:
    """The first name in ``sources`` that only the editor page has, or None when the bare page serves."""
    for source in sources:
        found = _GUI_NAMES.search(source or "")
        if found:
            return found.group(1)
    return None
