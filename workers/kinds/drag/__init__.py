"""The ``drag`` kind inside a worker: single-step drag jobs (set up the view, compute the exact regions, ask once,
drag for real, verify), and its contract with the driver (``DragSpec``, ``DragPayload``, ``DragAttempt``...).

The driver finds the drag agents through the registry (``workers.agent_api.agent_class(name, "drag")``). The
runner and the page's steps (``DragRunner``, ``show``, ``view_held``, ``SETTLE_MS``) need the browser stack, so
they are imported on first use: importing this package (what the kind registry does) stays light.
"""

import typing

import workers
from workers.kinds.drag._contract import (
    CONNECTIONS_OF,
    DRAG_SETTINGS,
    CanvasSource,
    DragAttempt,
    DragPayload,
    DragSource,
    DragSpec,
    DragType,
    ExpectedConnection,
    FlyoutSource,
)
from workers.kinds.drag._kind import DRAG, DragKind

if typing.TYPE_CHECKING:
    from workers.kinds.drag._page import SETTLE_MS, show, view_held
    from workers.kinds.drag._runner import DragRunner

__getattr__ = workers.lazy_exports(
    __name__, {"._page": ("SETTLE_MS", "show", "view_held"), "._runner": ("DragRunner",)}
)

__all__ = [
    "CONNECTIONS_OF",
    "DRAG",
    "DRAG_SETTINGS",
    "SETTLE_MS",
    "CanvasSource",
    "DragAttempt",
    "DragKind",
    "DragPayload",
    "DragRunner",
    "DragSource",
    "DragSpec",
    "DragType",
    "ExpectedConnection",
    "FlyoutSource",
    "show",
    "view_held",
]
