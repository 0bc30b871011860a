"""The single-step drag benchmark inside a worker: set up the view, compute the exact regions, ask, drag, verify.

The runner (``workers.drag._runner.DragRunner``) is imported by the worker actor itself, so the driver,
which only validates agents here, does not load the browser stack.
"""

from workers.drag._agents import DRAG_AGENTS, DragAnswer, DragQuestion, drag_agent

__all__ = ["DRAG_AGENTS", "DragAnswer", "DragQuestion", "drag_agent"]
