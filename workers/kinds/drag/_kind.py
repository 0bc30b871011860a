"""The ``drag`` kind as a worker runs it: one drag job in the worker's editor pool."""

from __future__ import annotations

from pydantic import BaseModel

from workers.contract import JobResult, WorkerJob
from workers.kinds._protocol import AgentGroup, WorkerHost
from workers.kinds.drag._contract import DragPayload, DragSpec


class DragKind:
    """Drag jobs: the view set up, the exact regions computed, one answer, one real drag, verified."""

    name = "drag"
    specs: tuple[type[BaseModel], ...] = (DragSpec,)
    payloads: tuple[type[BaseModel], ...] = (DragPayload,)
    code: tuple[str, ...] = ("kinds/drag/",)
    """This folder: no other kind nor the core imports it (it uses the agents' coordinate helpers and primitive
    mode's element list, which therefore stay core)."""

    needs_browser = True
    agents: AgentGroup | None = AgentGroup(
        group="scratchworld.drag_agents", methods=("answer",), base="workers.agent_api.DragAgentBase"
    )

    async def run(self, host: WorkerHost, spec: WorkerJob, payload: BaseModel) -> JobResult:
        from workers.kinds.drag._runner import DragRunner  # the browser stack, on the first job

        if not (isinstance(spec, DragSpec) and isinstance(payload, DragPayload)):
            return JobResult.errored(spec, "internal_error", "a drag job needs a drag spec and a drag payload")
        if spec.model is not None:
            await host.load_litellm()
        browser = await host.browser()
        drags = host.kind_state.get(self.name)
        if not isinstance(drags, DragRunner) or drags.pool is not browser.pool:  # one DragRunner per editor pool
            drags = host.kind_state[self.name] = DragRunner(browser.pool)
        return await host.in_browser(spec, browser.session, drags.run(spec, payload))


DRAG = DragKind()
