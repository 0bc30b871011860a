"""Suites of every benchmark (one generic layer) and the task suites: our own format and upstream clones."""

from scratchworld_dist.suites._detect import LOADERS, load_suite, loader_for, suite_instructions
from scratchworld_dist.suites._generic import BaseSuite, SuiteKind, SuiteLoader
from scratchworld_dist.suites._loading import find_loader, load_with
from scratchworld_dist.suites._native import NativeSuiteLoader
from scratchworld_dist.suites._problems import ProblemEffect, SuiteProblem, SuiteProblems, raise_problems
from scratchworld_dist.suites._stability import (
    StabilityMarks,
    SuiteStability,
    UnstableTest,
    known_stability,
    read_stability,
    scripts_digest,
    stability_file,
    stability_marks,
)
from scratchworld_dist.suites._task import (
    CATEGORIES,
    Suite,
    Task,
    TaskCategory,
    default_timing,
    read_trajectory,
    task_id_problem,
)
from scratchworld_dist.suites._upstream import UPSTREAM_TIMEOUT_S, UpstreamSuiteLoader, find_golden

__all__ = [
    "CATEGORIES",
    "LOADERS",
    "UPSTREAM_TIMEOUT_S",
    "BaseSuite",
    "NativeSuiteLoader",
    "ProblemEffect",
    "StabilityMarks",
    "Suite",
    "SuiteKind",
    "SuiteLoader",
    "SuiteProblem",
    "SuiteProblems",
    "SuiteStability",
    "Task",
    "TaskCategory",
    "UnstableTest",
    "UpstreamSuiteLoader",
    "default_timing",
    "find_golden",
    "find_loader",
    "known_stability",
    "load_suite",
    "load_with",
    "loader_for",
    "raise_problems",
    "read_stability",
    "read_trajectory",
    "scripts_digest",
    "stability_file",
    "stability_marks",
    "suite_instructions",
    "task_id_problem",
]
