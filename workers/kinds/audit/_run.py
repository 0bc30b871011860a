"""Running an audit job on a worker: the variant evaluated in the recycled evaluation editors, under the task's
profile and clock, exactly as an episode's final project (or a regrade) is. A variant the tests misjudge (a
mutant that passes, a refactoring that fails) is then traced with the golden, under one seed, to tell by
behaviour whether it is equivalent to the golden."""

from __future__ import annotations

import json
from functools import lru_cache

from pydantic import BaseModel

from workers.contract import AuditObservation, AuditSpec, JobResult, Sb3Archive, TaskPayload, WorkerJob
from workers.episode import judged
from workers.evaluation import Evaluator, first_difference
from workers.kinds._protocol import WorkerHost

EVALUATED = "evaluated"
"""Stop reason of an audit job's result."""

TRACE_SEED = 0
"""The seed of ``Math.random`` both traces are recorded under."""


async def run_variant(host: WorkerHost, spec: WorkerJob, task: BaseModel) -> JobResult:
    if not (isinstance(spec, AuditSpec) and isinstance(task, TaskPayload)):
        return JobResult.errored(spec, "internal_error", "an audit job needs its spec and its task's payload")
    if task.golden_project is None:
        return JobResult.errored(spec, "task_invalid", f"task {task.task_id} has no golden project to vary")
    runner = await host.browser()
    return await host.in_browser(spec, runner.session, _audit(runner.evaluator, spec, task, task.golden_project))


async def _audit(evaluator: Evaluator, spec: AuditSpec, task: TaskPayload, golden: bytes) -> JobResult:
    project = _variant(golden, spec.project_json)
    result = await judged(evaluator, project, task, spec.project_limits, spec.job_id, spec.attempt, EVALUATED)
    misjudged = (spec.variant == "mutant" and result.outcome == "passed") or (
        spec.variant == "refactoring" and result.outcome == "failed"
    )
    if not misjudged:
        return result
    theirs = await evaluator.evaluate_traced(golden, task.evaluation, spec.project_limits, random_seed=TRACE_SEED)
    ours = await evaluator.evaluate_traced(project, task.evaluation, spec.project_limits, random_seed=TRACE_SEED)
    if theirs.trace is None or ours.trace is None:
        return result  # a page that could not record: the verdict stands, unobserved
    difference = first_difference(theirs.trace, ours.trace)
    detail = AuditObservation(
        observed="equivalent" if difference is None else "differs",
        difference=None if difference is None else difference.describe(),
        truncated=theirs.trace.truncated or ours.trace.truncated,
    )
    return result.model_copy(update={"detail": detail})


@lru_cache(maxsize=8)
def _archive(golden: bytes) -> Sb3Archive:
    return Sb3Archive(golden)


def _variant(golden: bytes, project_json: str) -> bytes:
    """The golden's assets with the variant's project.json (its archive kept for the task's next variants)."""
    return _archive(golden).with_project(json.loads(project_json))
