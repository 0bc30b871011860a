"""The ``drag`` kind: single-step drag jobs (one observation, one model call, one real drag, verified)."""

from __future__ import annotations

from pydantic import BaseModel

from workers.contract import DragPayload, DragSpec, JobResult, WorkerJob
from workers.kinds._protocol import WorkerHost


class DragKind:
    """Drag jobs (see ``workers.kinds.drag._run``)."""

    name = "drag"
    specs: tuple[type[BaseModel], ...] = (DragSpec,)
    payloads: tuple[type[BaseModel], ...] = (DragPayload,)
    code: tuple[str, ...] = ("drag", "kinds/drag/_run.py")
    """workers/drag is imported by no other kind's runner nor by the core (it uses agents' coordinate
    helpers and primitive's element list, which therefore stay core)."""

    needs_browser = True

    async def run(self, host: WorkerHost, spec: WorkerJob, payload: BaseModel) -> JobResult:
        from workers.kinds.drag._run import run_drag

        return await run_drag(host, spec, payload)


DRAG = DragKind()
