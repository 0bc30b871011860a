"""Task suites: our own format and upstream ScratchWorld clones, behind one interface."""

from scratchworld_dist.suites._detect import LOADERS, SuiteLoader, load_suite, loader_for
from scratchworld_dist.suites._native import NativeSuiteLoader
from scratchworld_dist.suites._problems import SuiteProblems
from scratchworld_dist.suites._task import (
    CATEGORIES,
    Suite,
    SuiteKind,
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
    "NativeSuiteLoader",
    "Suite",
    "SuiteKind",
    "SuiteLoader",
    "SuiteProblems",
    "Task",
    "TaskCategory",
    "UpstreamSuiteLoader",
    "default_timing",
    "find_golden",
    "load_suite",
    "loader_for",
    "read_trajectory",
    "task_id_problem",
]
