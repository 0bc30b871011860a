"""The ``perception`` kind as a worker runs it: a question about a stored screenshot, no browser."""

from __future__ import annotations

from pydantic import BaseModel

from workers.contract import JobResult, WorkerJob
from workers.kinds._protocol import AgentGroup, WorkerHost
from workers.kinds.perception._contract import PerceptionPayload, PerceptionSpec


class PerceptionKind:
    """Perception jobs: one model call (or a scripted answer), scored both ways."""

    name = "perception"
    specs: tuple[type[BaseModel], ...] = (PerceptionSpec,)
    payloads: tuple[type[BaseModel], ...] = (PerceptionPayload,)
    code: tuple[str, ...] = ("kinds/perception/",)
    """This folder: no other kind nor the core imports it."""

    needs_browser = False
    agents: AgentGroup | None = AgentGroup(
        group="scratchworld.perception_agents", methods=("answer",), base="workers.agent_api.PerceptionAgentBase"
    )

    async def run(self, host: WorkerHost, spec: WorkerJob, payload: BaseModel) -> JobResult:
        from workers.kinds.perception._runner import run_perception  # the model stack, on the first job

        if not (isinstance(spec, PerceptionSpec) and isinstance(payload, PerceptionPayload)):
            return JobResult.errored(spec, "internal_error", "a perception job needs its spec and its item")
        if spec.model is not None:
            await host.load_litellm()
        return await run_perception(spec, payload)


PERCEPTION = PerceptionKind()
