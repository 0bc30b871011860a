"""The single-step drag benchmark's tasks: upstream's 60 and our own format, behind one loader; and making and
validating a suite in a real editor (``make_drag_suite``, ``validate_drag_tasks``), which need the browser stack
and so are imported on first use."""

import typing

import workers
from scratchworld_dist.kinds.drag.items._detect import DRAG_LOADERS, load_drag_suite
from scratchworld_dist.kinds.drag.items._layout import PALETTE_CATEGORIES, UPSTREAM_VIEWPORT
from scratchworld_dist.kinds.drag.items._native import NativeDragLoader, write_drag_suite
from scratchworld_dist.kinds.drag.items._suite import DragSuite
from scratchworld_dist.kinds.drag.items._task import DragTask, UpstreamAction, UpstreamDragReference
from scratchworld_dist.kinds.drag.items._upstream import UpstreamDragLoader
from workers.contract import ConnectionKind, DragView, PaletteCategory
from workers.kinds.drag import CONNECTIONS_OF, CanvasSource, DragSource, DragType, ExpectedConnection, FlyoutSource

if typing.TYPE_CHECKING:
    from scratchworld_dist.kinds.drag.items._make import MadeSuite, make_drag_suite
    from scratchworld_dist.kinds.drag.items._validate import DragTaskCheck, validate_drag_tasks

__getattr__ = workers.lazy_exports(
    __name__,
    {"._make": ("MadeSuite", "make_drag_suite"), "._validate": ("DragTaskCheck", "validate_drag_tasks")},
)

__all__ = [
    "CONNECTIONS_OF",
    "DRAG_LOADERS",
    "PALETTE_CATEGORIES",
    "UPSTREAM_VIEWPORT",
    "CanvasSource",
    "ConnectionKind",
    "DragSource",
    "DragSuite",
    "DragTask",
    "DragTaskCheck",
    "DragType",
    "DragView",
    "ExpectedConnection",
    "FlyoutSource",
    "MadeSuite",
    "NativeDragLoader",
    "PaletteCategory",
    "UpstreamAction",
    "UpstreamDragLoader",
    "UpstreamDragReference",
    "load_drag_suite",
    "make_drag_suite",
    "validate_drag_tasks",
    "write_drag_suite",
]
