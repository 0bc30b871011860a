"""Running an audit job on a worker: the variant evaluated in the recycled evaluation editors, under the task's
profile and clock, exactly as an episode's final project is."""

from __future__ import annotations

import json
import time
from functools import lru_cache

from pydantic import BaseModel

from workers.contract import AuditSpec, EpisodeTimings, JobResult, Sb3Archive, TaskPayload, WorkerJob, outcome_of
from workers.evaluation import Evaluator
from workers.kinds._protocol import WorkerHost

EVALUATED = "evaluated"
"""Stop reason of an audit job's result."""


async def run_variant(host: WorkerHost, spec: WorkerJob, task: BaseModel) -> JobResult:
    if not (isinstance(spec, AuditSpec) and isinstance(task, TaskPayload)):
        return JobResult.errored(spec, "internal_error", "an audit job needs its spec and its task's payload")
    if task.golden_project is None:
        return JobResult.errored(spec, "task_invalid", f"task {task.task_id} has no golden project to vary")
    runner = await host.browser()
    return await host.in_browser(spec, runner.session, _evaluate(runner.evaluator, spec, task))


async def _evaluate(evaluator: Evaluator, spec: AuditSpec, task: TaskPayload) -> JobResult:
    started, clock = time.time(), time.perf_counter()
    project = _variant(task.golden_project or b"", spec.project_json)
    evaluation = await evaluator.evaluate(project, task.evaluation, spec.project_limits)
    elapsed = time.perf_counter() - clock
    outcome, error_class = outcome_of(evaluation)
    return JobResult(
        job_id=spec.job_id,
        attempt=spec.attempt,
        outcome=outcome,
        error_class=error_class,
        error_message=evaluation.error.message if error_class and evaluation.error else None,
        stop_reason=error_class or EVALUATED,
        evaluation=evaluation,
        timings=EpisodeTimings(evaluation_s=elapsed, total_s=elapsed),
        started_at=started,
        finished_at=time.time(),
    )


@lru_cache(maxsize=8)
def _archive(golden: bytes) -> Sb3Archive:
    return Sb3Archive(golden)


def _variant(golden: bytes, project_json: str) -> bytes:
    """The golden's assets with the variant's project.json (its archive kept for the task's next variants)."""
    return _archive(golden).with_project(json.loads(project_json))
