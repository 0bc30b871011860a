"""Choosing a drag-suite loader from what a folder looks like."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from scratchworld_dist.kinds.drag.items._native import SUITE_FILE, NativeDragLoader
from scratchworld_dist.kinds.drag.items._suite import DragSuite
from scratchworld_dist.kinds.drag.items._upstream import PROJECTS_DIR, TASKS_DIR, UpstreamDragLoader
from scratchworld_dist.suites import SuiteLoader, load_with

DRAG_LOADERS: tuple[SuiteLoader[DragSuite], ...] = (NativeDragLoader(), UpstreamDragLoader())

NOT_A_DRAG_SUITE = (
    f"not a drag suite: expected {SUITE_FILE} (a scratchworld_dist drag suite) or {TASKS_DIR}/ and "
    f"{PROJECTS_DIR}/ (a clone of the upstream ScratchWorld repository)"
)


def _clone_above(root: Path) -> Sequence[Path]:
    """A clone's ``single_step_drag_benchmark/`` or its ``tasks/`` folder stands for the clone."""
    if root.name == TASKS_DIR.name and root.parent.name == TASKS_DIR.parent.name:
        return (root.parent.parent,)
    if root.name == TASKS_DIR.parent.name:
        return (root.parent,)
    return ()


def load_drag_suite(path: str | Path) -> DragSuite:
    """Load the drag suite at ``path``, detecting its layout.

    Raises ``SuiteError`` only when there is no suite to speak of (no folder, no recognisable
    layout, an unreadable manifest); a bad task is left out, or kept without a view, and listed
    in ``DragSuite.problems``.
    """
    return load_with(path, DRAG_LOADERS, NOT_A_DRAG_SUITE, _clone_above)
