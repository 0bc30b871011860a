"""A perception attempt as a row of the run's ``perception`` table."""

from __future__ import annotations

from scratchworld_dist.kinds.perception._plan import PerceptionBody
from scratchworld_dist.results import PerceptionRow, shared_image_path
from scratchworld_dist.sweep import JobSpec
from workers.contract import JobResult, PerceptionAttempt


def perception_row(job: JobSpec, result: JobResult) -> PerceptionRow:
    attempt, body = result.detail, job.body
    if not isinstance(attempt, PerceptionAttempt) or not isinstance(body, PerceptionBody):
        raise ValueError(f"job {job.job_id} is not a perception job")
    score = attempt.score
    return PerceptionRow(
        job_id=job.job_id,
        attempt=result.attempt,
        item_id=job.task_id,
        question=body.item.question,
        kind=body.item.kind,
        tag=body.item.tag,
        answer_format=body.item.answer_format,
        value_kind=body.item.value_kind,
        model=job.model_name,
        agent=job.agent_label,
        seed=job.seed,
        expected=attempt.expected,
        reply=attempt.reply,
        extracted=score.extracted,
        parse=score.parse,
        strict_correct=score.strict,
        normalized_correct=score.normalized,
        screenshot=shared_image_path(attempt.screenshot_sha256),
    )
