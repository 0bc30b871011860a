"""Choosing a task-suite loader from what a folder looks like."""

from __future__ import annotations

import functools
from collections.abc import Sequence
from pathlib import Path

from scratchworld_dist._errors import ScratchWorldError
from scratchworld_dist.suites._generic import SuiteLoader
from scratchworld_dist.suites._loading import find_loader, load_with
from scratchworld_dist.suites._native import SUITE_FILE, NativeSuiteLoader
from scratchworld_dist.suites._task import Suite
from scratchworld_dist.suites._upstream import PROJECTS_DIR, UpstreamSuiteLoader

LOADERS: tuple[SuiteLoader[Suite], ...] = (NativeSuiteLoader(), UpstreamSuiteLoader())

NOT_A_SUITE = (
    f"not a task suite: expected {SUITE_FILE} (a scratchworld_dist suite) or tasks/ and "
    f"{PROJECTS_DIR}/ (a clone of the upstream ScratchWorld repository)"
)


def _clone_above(root: Path) -> Sequence[Path]:
    """A clone's ``tasks/`` folder stands for the clone."""
    return (root.parent,) if root.name == "tasks" else ()


def loader_for(root: Path) -> tuple[SuiteLoader[Suite], Path]:
    """The loader that recognises ``root`` (or, for a clone's ``tasks/`` folder, its parent)."""
    return find_loader(root, LOADERS, NOT_A_SUITE, _clone_above)


def load_suite(path: str | Path, task_list: str | None = None) -> Suite:
    """Load the suite at ``path``, detecting its layout; ``task_list`` picks an upstream list."""
    loaders = (NativeSuiteLoader(task_list), UpstreamSuiteLoader(task_list=task_list))
    return load_with(path, loaders, NOT_A_SUITE, _clone_above)


@functools.lru_cache(maxsize=16)
def suite_instructions(root: str, suite_hash: str) -> dict[str, str]:
    """The instructions of the suite a run found at ``root``, by task id, read once per suite content
    (``suite_hash``: a changed suite is read again); none when the suite is no longer there."""
    try:
        return {task.id: task.instruction for task in load_suite(Path(root)).tasks}
    except (ScratchWorldError, OSError):
        return {}
