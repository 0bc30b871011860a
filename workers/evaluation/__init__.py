"""Evaluation: a project and a task's script in a clean editor, under a profile, to a verdict."""

from workers.evaluation._evaluator import Evaluator, project_refusal, wall_limit_s
from workers.evaluation._profiles import apply_profile
from workers.evaluation._report import ReportError, TestReport, parse_report

__all__ = [
    "Evaluator",
    "ReportError",
    "TestReport",
    "apply_profile",
    "parse_report",
    "project_refusal",
    "wall_limit_s",
]
