"""Evaluation: a project and a task's script in a clean editor, under a profile, to a verdict."""

from workers.evaluation._evaluator import Evaluator, judged, project_refusal, wall_limit_s
from workers.evaluation._page_runs import ObservedReads, PageRun, explored, observed_tests_run
from workers.evaluation._profiles import apply_profile
from workers.evaluation._report import ReportError, TestReport, parse_report
from workers.evaluation._trace import (
    DEFAULT_TRACE_CHARS,
    ObservableTrace,
    TracedEvaluation,
    TraceFrame,
)
from workers.evaluation._trace_compare import TraceDifference, first_difference

__all__ = [
    "DEFAULT_TRACE_CHARS",
    "Evaluator",
    "ObservableTrace",
    "ObservedReads",
    "PageRun",
    "ReportError",
    "TestReport",
    "TraceDifference",
    "TraceFrame",
    "TracedEvaluation",
    "apply_profile",
    "explored",
    "first_difference",
    "judged",
    "observed_tests_run",
    "parse_report",
    "project_refusal",
    "wall_limit_s",
]
