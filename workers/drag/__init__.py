"""The single-step drag benchmark inside a worker: set up the view, compute the exact regions, ask, drag, verify.

The driver finds the drag agents through the registry (``workers.agent_api.agent_class(name, "drag")``, entry
points of ``scratchworld.drag_agents``). The runner and the page's steps (``DragRunner``, ``show``,
``view_held``, ``SETTLE_MS``) need the browser stack, so they are imported on first use.
"""

import typing

import workers

if typing.TYPE_CHECKING:
    from workers.drag._page import SETTLE_MS, show, view_held
    from workers.drag._runner import DragRunner

__getattr__ = workers.lazy_exports(
    __name__, {"._page": ("SETTLE_MS", "show", "view_held"), "._runner": ("DragRunner",)}
)

__all__ = ["SETTLE_MS", "DragRunner", "show", "view_held"]
