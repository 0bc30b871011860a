"""Running a drag job on a worker, in its browser's editor pool: the actor's former drag branch, unchanged."""

from __future__ import annotations

from pydantic import BaseModel

from workers.contract import DragPayload, DragSpec, JobResult, WorkerJob
from workers.drag import DragRunner
from workers.kinds._protocol import WorkerHost


async def run_drag(host: WorkerHost, spec: WorkerJob, task: BaseModel) -> JobResult:
    if not (isinstance(spec, DragSpec) and isinstance(task, DragPayload)):
        return JobResult.errored(spec, "internal_error", "a drag job needs a drag spec and a drag payload")
    if spec.model is not None:
        await host.load_litellm()
    runner = await host.browser()
    drags = host.kind_state.get("drag")
    if not isinstance(drags, DragRunner) or drags.pool is not runner.pool:  # one DragRunner per editor pool
        drags = host.kind_state["drag"] = DragRunner(runner.pool)
    return await host.in_browser(spec, runner.session, drags.run(spec, task))
