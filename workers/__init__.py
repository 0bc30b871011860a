"""What runs inside a worker: the browser session, the editor bridge and evaluation."""

from workers._browser import CHROMIUM_ARGS, BrowserConfig, BrowserSession
from workers._editor import Editor, EditorStatus
from workers._editor_server import EditorAssets, EditorServer
from workers._eval_result import VERDICT_ERROR_KINDS, EvalError, EvalErrorKind, EvalResult, EvalTimings, TestVerdict
from workers._evaluation import Evaluator
from workers._evaluation_spec import EvaluationSpec

__all__ = [
    "CHROMIUM_ARGS",
    "VERDICT_ERROR_KINDS",
    "BrowserConfig",
    "BrowserSession",
    "Editor",
    "EditorAssets",
    "EditorServer",
    "EditorStatus",
    "EvalError",
    "EvalErrorKind",
    "EvalResult",
    "EvalTimings",
    "EvaluationSpec",
    "Evaluator",
    "TestVerdict",
]
