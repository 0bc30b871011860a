"""A regrade on the worker: the stored project evaluated as an episode's final project is, no agent.

It goes through the runner's ``Evaluator`` (the worker's recycled evaluation editors, the task's
profile and clock), so a regrade's verdict is made exactly as the episode's own would have been.
"""

from __future__ import annotations

import time

from workers.contract import EpisodeTimings, JobResult, ProjectLimits, RegradeSpec, TaskPayload, outcome_of
from workers.evaluation import Evaluator

REGRADED = "regraded"
"""Stop reason of a regrade's result (the driver keeps the source's in the row)."""


async def regrade(evaluator: Evaluator, spec: RegradeSpec, task: TaskPayload) -> JobResult:
    """The verdict on ``spec.project`` under ``task.evaluation``, as an episode result without steps."""
    return await judged(evaluator, spec.project, task, spec.project_limits, spec.job_id, spec.attempt, REGRADED)


async def judged(
    evaluator: Evaluator,
    project: bytes,
    task: TaskPayload,
    limits: ProjectLimits,
    job_id: str,
    attempt: int,
    stop_reason: str,
) -> JobResult:
    """The verdict on ``project`` under ``task.evaluation``, as a result without steps (``stop_reason``: what
    the job was, when the evaluation gave a verdict)."""
    started, clock = time.time(), time.perf_counter()
    evaluation = await evaluator.evaluate(project, task.evaluation, limits)
    elapsed = time.perf_counter() - clock
    outcome, error_class = outcome_of(evaluation)
    return JobResult(
        job_id=job_id,
        attempt=attempt,
        outcome=outcome,
        error_class=error_class,
        error_message=evaluation.error.message if error_class and evaluation.error else None,
        stop_reason=error_class or stop_reason,
        evaluation=evaluation,
        timings=EpisodeTimings(evaluation_s=elapsed, total_s=elapsed),
        started_at=started,
        finished_at=time.time(),
    )
