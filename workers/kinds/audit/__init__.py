"""The ``audit`` kind: a variant of a task's golden project evaluated by the task's tests, no agent."""

from __future__ import annotations

from pydantic import BaseModel

from workers.contract import AuditSpec, JobResult, TaskPayload, WorkerJob
from workers.kinds._protocol import WorkerHost


class AuditKind:
    """Audit jobs (see ``workers.kinds.audit._run``)."""

    name = "audit"
    specs: tuple[type[BaseModel], ...] = (AuditSpec,)
    payloads: tuple[type[BaseModel], ...] = (TaskPayload,)
    code: tuple[str, ...] = ("kinds/audit/_run.py",)
    """Its dispatch; the evaluation it runs is the episodes' own (core)."""

    needs_browser = True

    async def run(self, host: WorkerHost, spec: WorkerJob, payload: BaseModel) -> JobResult:
        from workers.kinds.audit._run import run_variant

        return await run_variant(host, spec, payload)


AUDIT = AuditKind()
