"""Running a perception job on a worker (no browser): the actor's former perception branch, unchanged."""

from __future__ import annotations

from pydantic import BaseModel

from workers.contract import JobResult, PerceptionPayload, PerceptionSpec, WorkerJob
from workers.kinds._protocol import WorkerHost
from workers.perception import run_perception


async def run_item(host: WorkerHost, spec: WorkerJob, item: BaseModel) -> JobResult:
    if not (isinstance(spec, PerceptionSpec) and isinstance(item, PerceptionPayload)):
        return JobResult.errored(spec, "internal_error", "a perception job needs its spec and its item")
    if spec.model is not None:
        await host.load_litellm()
    return await run_perception(spec, item)
