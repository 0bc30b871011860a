"""Running an audit job on a worker: the variant evaluated in the recycled evaluation editors, under the task's
profile and clock, exactly as an episode's final project (or a regrade) is."""

from __future__ import annotations

import json
from functools import lru_cache

from pydantic import BaseModel

from workers.contract import AuditSpec, JobResult, Sb3Archive, TaskPayload, WorkerJob
from workers.episode import judged
from workers.kinds._protocol import WorkerHost

EVALUATED = "evaluated"
"""Stop reason of an audit job's result."""


async def run_variant(host: WorkerHost, spec: WorkerJob, task: BaseModel) -> JobResult:
    if not (isinstance(spec, AuditSpec) and isinstance(task, TaskPayload)):
        return JobResult.errored(spec, "internal_error", "an audit job needs its spec and its task's payload")
    if task.golden_project is None:
        return JobResult.errored(spec, "task_invalid", f"task {task.task_id} has no golden project to vary")
    project = _variant(task.golden_project, spec.project_json)
    runner = await host.browser()
    work = judged(runner.evaluator, project, task, spec.project_limits, spec.job_id, spec.attempt, EVALUATED)
    return await host.in_browser(spec, runner.session, work)


@lru_cache(maxsize=8)
def _archive(golden: bytes) -> Sb3Archive:
    return Sb3Archive(golden)


def _variant(golden: bytes, project_json: str) -> bytes:
    """The golden's assets with the variant's project.json (its archive kept for the task's next variants)."""
    return _archive(golden).with_project(json.loads(project_json))
