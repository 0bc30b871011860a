"""The perception kind's own table, ``perception``: one row per attempt."""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict

from scratchworld_dist.kinds.perception._plan import PerceptionBody
from scratchworld_dist.results import shared_image_path
from scratchworld_dist.sweep import JobSpec
from workers.contract import JobResult
from workers.kinds.perception import PerceptionAttempt


class PerceptionRow(BaseModel):
    """What one perception attempt answered and how it scored both ways (a row of ``perception/``)."""

    model_config = ConfigDict(frozen=True)

    job_id: str
    attempt: int
    item_id: str
    question: str
    kind: str
    """connection, existence or field."""

    tag: str
    """The item's finer class (upstream's tags, e.g. ``connection_no_hard``, or ours)."""

    answer_format: str
    """yes_no or value."""

    value_kind: str | None
    """For value items: number, text or dropdown."""

    model: str
    agent: str
    seed: int
    expected: str
    reply: str
    """The answer as given: the model's raw reply, or a scripted agent's answer."""

    extracted: str | None
    """The answer the normalized scoring read out of the reply (null when it found none)."""

    parse: str
    """ok, no_answer (empty reply) or unparsed (no answer of the asked form in it)."""

    strict_correct: bool
    """Upstream's scoring: the stripped reply equals the answer (YES/NO case-insensitively)."""

    normalized_correct: bool
    """Ours (decides the job's outcome): the final answer read from the reply, trimmed, numbers as numbers."""

    screenshot: str
    """The item's screenshot, relative to the run directory (``images/<sha256>.png``, stored once per run)."""


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
