"""What runs inside a worker: the browser session, the editor bridge and evaluation."""

from workers._actions import (
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
from workers._browser import CHROMIUM_ARGS, BrowserConfig, BrowserSession
from workers._composite import CompositeObservation
from workers._editor import Editor, EditorStatus
from workers._editor_pool import EditorPool
from workers._editor_server import EditorAssets, EditorServer
from workers._envelope import ActionEnvelope, ActionFailure
from workers._episode import (
    PERMANENT_ERRORS,
    AgentName,
    EpisodeResult,
    EpisodeSpec,
    EpisodeTimings,
    ErrorClass,
    Mode,
    ModelSpec,
    Outcome,
    StepRecord,
    TaskPayload,
    WorkerInfo,
    outcome_of,
)
from workers._episode_runner import EpisodeRunner
from workers._eval_result import VERDICT_ERROR_KINDS, EvalError, EvalErrorKind, EvalResult, EvalTimings, TestVerdict
from workers._evaluation import Evaluator, project_refusal
from workers._evaluation_spec import EvaluationClock, EvaluationSpec
from workers._fingerprint import HarnessFingerprint, describe_differences, harness_fingerprint
from workers._profiles import EvaluationProfile, ProfileConditions
from workers._sb3_reader import MIB, ProjectLimits, check_project
from workers._synthetic import SyntheticEpisodes, run_synthetic
from workers.llm._limiter import RateLimits
from workers.llm._settings import CoordinateSystem, LLMSettings
from workers.primitive._settings import ObservationSettings

__all__ = [
    "CHROMIUM_ARGS",
    "FINAL_ACTIONS",
    "MIB",
    "PERMANENT_ERRORS",
    "VERDICT_ERROR_KINDS",
    "Action",
    "ActionEnvelope",
    "ActionFailure",
    "AgentName",
    "BrowserConfig",
    "BrowserSession",
    "CompositeAction",
    "CompositeObservation",
    "CoordinateSystem",
    "Done",
    "Editor",
    "EditorAssets",
    "EditorPool",
    "EditorServer",
    "EditorStatus",
    "EpisodeResult",
    "EpisodeRunner",
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
    "Evaluator",
    "Failed",
    "HarnessFingerprint",
    "InvalidReply",
    "LLMSettings",
    "LoadProject",
    "Mode",
    "ModelSpec",
    "ObservationSettings",
    "Outcome",
    "PrimitiveAction",
    "ProfileConditions",
    "ProjectLimits",
    "RateLimits",
    "StepRecord",
    "SyntheticEpisodes",
    "TaskPayload",
    "TestVerdict",
    "WorkerInfo",
    "check_project",
    "composite_action",
    "describe_differences",
    "harness_fingerprint",
    "outcome_of",
    "primitive_action",
    "project_refusal",
    "run_synthetic",
]
