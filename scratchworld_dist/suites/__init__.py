"""Suites of every benchmark (one generic layer) and the task suites: our own format and upstream clones."""

from scratchworld_dist.suites._detect import LOADERS, load_suite, loader_for, suite_instructions
from scratchworld_dist.suites._generic import BaseSuite, SuiteKind, SuiteLoader
from scratchworld_dist.suites._loading import find_loader, load_with
from scratchworld_dist.suites._native import NativeSuiteLoader
from scratchworld_dist.suites._problems import ProblemEffect, SuiteProblem, SuiteProblems, raise_problems
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
    "Suite",
    "SuiteKind",
    "SuiteLoader",
    "SuiteProblem",
    "SuiteProblems",
    "Task",
    "TaskCategory",
    "UpstreamSuiteLoader",
    "default_timing",
    "find_golden",
    "find_loader",
    "load_suite",
    "load_with",
    "loader_for",
    "raise_problems",
    "read_trajectory",
    "suite_instructions",
    "task_id_problem",
]
