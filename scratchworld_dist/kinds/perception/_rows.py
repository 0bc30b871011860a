"""A perception attempt as a row of the run's ``perception`` table."""

from __future__ import annotations

from scratchworld_dist.results import PerceptionRow, shared_image_path
from scratchworld_dist.sweep import JobSpec
from workers.contract import EpisodeResult


def perception_row(job: JobSpec, result: EpisodeResult) -> PerceptionRow:
    attempt, item = result.perception, job.perception
    if attempt is None or item is None:
        raise ValueError(f"job {job.job_id} is not a perception job")
    score = attempt.score
    return PerceptionRow(
        job_id=job.job_id,
        attempt=result.attempt,
        item_id=job.task_id,
        question=item.question,
        kind=item.kind,
        tag=item.tag,
        answer_format=item.answer_format,
        value_kind=item.value_kind,
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
