"""The ``perception`` kind: a question about a stored screenshot, one model call, both scorings; no editor."""

from __future__ import annotations

from pydantic import BaseModel

from workers.contract import JobResult, PerceptionPayload, PerceptionSpec, WorkerJob
from workers.kinds._protocol import WorkerHost


class PerceptionKind:
    """Perception jobs (see ``workers.kinds.perception._run``)."""

    name = "perception"
    specs: tuple[type[BaseModel], ...] = (PerceptionSpec,)
    payloads: tuple[type[BaseModel], ...] = (PerceptionPayload,)
    code: tuple[str, ...] = ("perception", "kinds/perception/_run.py")
    """workers/perception is imported by no other kind's runner nor by the core."""

    needs_browser = False

    async def run(self, host: WorkerHost, spec: WorkerJob, payload: BaseModel) -> JobResult:
        from workers.kinds.perception._run import run_item

        return await run_item(host, spec, payload)


PERCEPTION = PerceptionKind()
