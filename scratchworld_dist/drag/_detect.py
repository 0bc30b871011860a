"""Choosing a drag-suite loader from what a folder looks like."""

from __future__ import annotations

from pathlib import Path
from typing import Protocol

from scratchworld_dist._errors import SuiteError
from scratchworld_dist.drag._native import SUITE_FILE, NativeDragLoader
from scratchworld_dist.drag._suite import DragSuite
from scratchworld_dist.drag._upstream import PROJECTS_DIR, TASKS_DIR, UpstreamDragLoader


class DragSuiteLoader(Protocol):
    kind: str

    @staticmethod
    def handles(root: Path) -> bool: ...

    def load(self, root: Path) -> DragSuite: ...


DRAG_LOADERS: tuple[DragSuiteLoader, ...] = (NativeDragLoader(), UpstreamDragLoader())


def drag_loader_for(root: Path) -> tuple[DragSuiteLoader, Path]:
    """The loader that recognises ``root``, or a clone above it (``single_step_drag_benchmark/[tasks]``)."""
    candidates = [root]
    if root.name == TASKS_DIR.name and root.parent.name == TASKS_DIR.parent.name:
        candidates.append(root.parent.parent)
    elif root.name == TASKS_DIR.parent.name:
        candidates.append(root.parent)
    for candidate in candidates:
        for loader in DRAG_LOADERS:
            if loader.handles(candidate):
                return loader, candidate
    raise SuiteError(
        f"not a drag suite: expected {SUITE_FILE} (a scratchworld_dist drag suite) or {TASKS_DIR}/ and "
        f"{PROJECTS_DIR}/ (a clone of the upstream ScratchWorld repository)",
        root,
    )


def load_drag_suite(path: str | Path) -> DragSuite:
    """Load the drag suite at ``path``, detecting its layout.

    Raises ``SuiteError`` only when there is no suite to speak of (no folder, no recognisable
    layout, an unreadable manifest); a bad task is left out, or kept without a view, and listed
    in ``DragSuite.problems``.
    """
    root = Path(path).expanduser().absolute()
    if not root.is_dir():
        raise SuiteError("not a directory" if root.exists() else "no such directory", root)
    loader, suite_root = drag_loader_for(root)
    return loader.load(suite_root)
