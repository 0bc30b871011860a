"""The single-step drag benchmark inside a worker: set up the view, compute the exact regions, ask, drag, verify."""

from workers.drag._agents import DRAG_AGENTS, DragAnswer, DragQuestion, drag_agent
from workers.drag._runner import DragRunner

__all__ = ["DRAG_AGENTS", "DragAnswer", "DragQuestion", "DragRunner", "drag_agent"]
