"""The single-step drag benchmark inside a worker: set up the view, compute the exact regions, ask, drag, verify.

Nothing is exported here: the driver finds the drag agents through the registry
(``workers.agent_api.agent_class(name, "drag")``, entry points of ``scratchworld.drag_agents``); the agents
(``workers.drag._agents``) and the runner (``workers.drag._runner``) are imported where they run.
"""
