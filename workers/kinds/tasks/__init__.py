"""The ``tasks`` kind: multi-step episodes (an agent in the editor, then the evaluation), and regrades
of the projects they left (the evaluation alone, in the same recycled evaluation editors)."""

from __future__ import annotations

from pydantic import BaseModel

from workers.contract import EpisodeSpec, JobResult, RegradeSpec, TaskPayload, WorkerJob
from workers.kinds._protocol import WorkerHost


class TasksKind:
    """Episodes and regrades (see ``workers.kinds.tasks._run``)."""

    name = "tasks"
    specs: tuple[type[BaseModel], ...] = (EpisodeSpec, RegradeSpec)
    payloads: tuple[type[BaseModel], ...] = (TaskPayload,)
    code: tuple[str, ...] = ("kinds/tasks/_run.py",)
    """Only this kind's dispatch: the episode code itself (workers/episode, evaluation, composite, ...)
    is core, see ``workers.kinds._fingerprint``."""

    needs_browser = True

    async def run(self, host: WorkerHost, spec: WorkerJob, payload: BaseModel) -> JobResult:
        from workers.kinds.tasks._run import run_task

        return await run_task(host, spec, payload)


TASKS = TasksKind()
