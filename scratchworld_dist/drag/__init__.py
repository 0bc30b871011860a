"""The single-step drag benchmark's tasks: upstream's 60 and our own format, behind one loader."""

from scratchworld_dist.drag._detect import DRAG_LOADERS, DragSuiteLoader, load_drag_suite
from scratchworld_dist.drag._layout import PALETTE_CATEGORIES, UPSTREAM_VIEWPORT
from scratchworld_dist.drag._native import NativeDragLoader, write_drag_suite
from scratchworld_dist.drag._suite import DragProblem, DragSuite, ProblemEffect
from scratchworld_dist.drag._task import DragTask, UpstreamAction, UpstreamDragReference
from scratchworld_dist.drag._upstream import UpstreamDragLoader
from workers.contract import (
    CONNECTIONS_OF,
    CanvasSource,
    ConnectionKind,
    DragSource,
    DragType,
    DragView,
    ExpectedConnection,
    FlyoutSource,
    PaletteCategory,
)

__all__ = [
    "CONNECTIONS_OF",
    "DRAG_LOADERS",
    "PALETTE_CATEGORIES",
    "UPSTREAM_VIEWPORT",
    "CanvasSource",
    "ConnectionKind",
    "DragProblem",
    "DragSource",
    "DragSuite",
    "DragSuiteLoader",
    "DragTask",
    "DragType",
    "DragView",
    "ExpectedConnection",
    "FlyoutSource",
    "NativeDragLoader",
    "PaletteCategory",
    "ProblemEffect",
    "UpstreamAction",
    "UpstreamDragLoader",
    "UpstreamDragReference",
    "load_drag_suite",
    "write_drag_suite",
]
