"""Choosing a loader from what a folder looks like."""

from __future__ import annotations

from pathlib import Path
from typing import Protocol

from scratchworld_dist._errors import SuiteError
from scratchworld_dist.suites._native import SUITE_FILE, NativeSuiteLoader
from scratchworld_dist.suites._task import Suite
from scratchworld_dist.suites._upstream import PROJECTS_DIR, UpstreamSuiteLoader


class SuiteLoader(Protocol):
    kind: str

    @staticmethod
    def handles(root: Path) -> bool: ...

    def load(self, root: Path, task_list: str | None = None) -> Suite: ...


LOADERS: tuple[SuiteLoader, ...] = (NativeSuiteLoader(), UpstreamSuiteLoader())


def loader_for(root: Path) -> tuple[SuiteLoader, Path]:
    """The loader that recognises ``root`` (or, for a clone's ``tasks/`` folder, its parent)."""
    for candidate in (root, root.parent) if root.name == "tasks" else (root,):
        for loader in LOADERS:
            if loader.handles(candidate):
                return loader, candidate
    raise SuiteError(
        f"not a task suite: expected {SUITE_FILE} (a scratchworld_dist suite) or tasks/ and "
        f"{PROJECTS_DIR}/ (a clone of the upstream ScratchWorld repository)",
        root,
    )


def load_suite(path: str | Path, task_list: str | None = None) -> Suite:
    """Load the suite at ``path``, detecting its layout; ``task_list`` picks an upstream list."""
    root = Path(path).expanduser().absolute()
    if not root.is_dir():
        raise SuiteError("not a directory" if root.exists() else "no such directory", root)
    loader, suite_root = loader_for(root)
    return loader.load(suite_root, task_list)
