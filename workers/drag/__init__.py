"""The single-step drag benchmark inside a worker: set up the view, compute the exact regions, ask, drag, verify.

Only the agents' names and parameters are exported here (``checked_drag_agent``, ``needs_model``): the driver
validates configs with them without loading the browser stack. The agents (``workers.drag._agents``) and the
runner (``workers.drag._runner``) are imported where they run.
"""

from workers.drag._refs import DRAG_AGENTS, JitterParams, checked_drag_agent, needs_model

__all__ = ["DRAG_AGENTS", "JitterParams", "checked_drag_agent", "needs_model"]
