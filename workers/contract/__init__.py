"""The contract between the driver and its workers: the data and errors both sides share.

Pydantic models (what an episode is given and returns, the actions an agent takes and what
the environment answers, evaluation specs and verdicts, model and observation settings, project
limits, the harness fingerprint) and the single exception hierarchy. It imports pydantic and
the standard library only, so the driver, reports and plugins load it without a browser stack.
"""

from workers.contract._actions import (
    FINAL_ACTIONS,
    Action,
    CompositeAction,
    Done,
    Failed,
    InvalidReply,
    LoadProject,
    PrimitiveAction,
    composite_action,
    primitive_action,
)
from workers.contract._envelope import ActionEnvelope, ActionFailure
from workers.contract._episode import (
    PERMANENT_ERRORS,
    AgentName,
    EpisodeResult,
    EpisodeSpec,
    EpisodeTimings,
    ErrorClass,
    Mode,
    ModelErrorClass,
    Outcome,
    StepRecord,
    TaskPayload,
    WorkerInfo,
    outcome_of,
)
from workers.contract._errors import (
    BridgeError,
    ChromiumNotFoundError,
    EditorBundleMissingError,
    EditorCrashedError,
    EditorError,
    EditorNotReadyError,
    OCRError,
    ProjectFormatError,
    ProjectTooLargeError,
    RendererUnavailableError,
    ScratchWorldError,
)
from workers.contract._eval_result import (
    VERDICT_ERROR_KINDS,
    EvalError,
    EvalErrorKind,
    EvalResult,
    EvalTimings,
    ProfileConditions,
    TestVerdict,
)
from workers.contract._evaluation_spec import EvaluationClock, EvaluationProfile, EvaluationSpec
from workers.contract._harness import (
    ENVIRONMENT_PARTS,
    HarnessFingerprint,
    NodeReport,
    NodeSummary,
    describe_differences,
    fingerprint,
)
from workers.contract._model import CoordinateSystem, LLMSettings, ModelSpec, RateLimits, RetryPolicy
from workers.contract._observation_settings import ObservationSettings
from workers.contract._sb3 import MIB, ProjectLimits, check_project
from workers.contract._synthetic import SyntheticEpisodes

__all__ = [
    "ENVIRONMENT_PARTS",
    "FINAL_ACTIONS",
    "MIB",
    "PERMANENT_ERRORS",
    "VERDICT_ERROR_KINDS",
    "Action",
    "ActionEnvelope",
    "ActionFailure",
    "AgentName",
    "BridgeError",
    "ChromiumNotFoundError",
    "CompositeAction",
    "CoordinateSystem",
    "Done",
    "EditorBundleMissingError",
    "EditorCrashedError",
    "EditorError",
    "EditorNotReadyError",
    "EpisodeResult",
    "EpisodeSpec",
    "EpisodeTimings",
    "ErrorClass",
    "EvalError",
    "EvalErrorKind",
    "EvalResult",
    "EvalTimings",
    "EvaluationClock",
    "EvaluationProfile",
    "EvaluationSpec",
    "Failed",
    "HarnessFingerprint",
    "InvalidReply",
    "LLMSettings",
    "LoadProject",
    "Mode",
    "ModelErrorClass",
    "ModelSpec",
    "NodeReport",
    "NodeSummary",
    "OCRError",
    "ObservationSettings",
    "Outcome",
    "PrimitiveAction",
    "ProfileConditions",
    "ProjectFormatError",
    "ProjectLimits",
    "ProjectTooLargeError",
    "RateLimits",
    "RendererUnavailableError",
    "RetryPolicy",
    "ScratchWorldError",
    "StepRecord",
    "SyntheticEpisodes",
    "TaskPayload",
    "TestVerdict",
    "WorkerInfo",
    "check_project",
    "composite_action",
    "describe_differences",
    "fingerprint",
    "outcome_of",
    "primitive_action",
]
