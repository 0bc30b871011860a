"""The single-step drag benchmark inside a worker: set up the view, compute the exact regions, ask, drag, verify.

The agents' names and parameters (``checked_drag_agent``, ``needs_model``) are imported with the package: the
driver validates configs with them without loading the browser stack. The runner and the page's steps
(``DragRunner``, ``show``, ``view_held``, ``SETTLE_MS``) need that stack, so they are imported on first use.
"""

import typing

import workers
from workers.drag._refs import DRAG_AGENTS, JitterParams, checked_drag_agent, needs_model

if typing.TYPE_CHECKING:
    from workers.drag._page import SETTLE_MS, show, view_held
    from workers.drag._runner import DragRunner

__getattr__ = workers.lazy_exports(
    __name__, {"._page": ("SETTLE_MS", "show", "view_held"), "._runner": ("DragRunner",)}
)

__all__ = [
    "DRAG_AGENTS",
    "SETTLE_MS",
    "DragRunner",
    "JitterParams",
    "checked_drag_agent",
    "needs_model",
    "show",
    "view_held",
]
