"""The audit kind's own table, ``audits``: one row per evaluated variant, with what the grader made of it."""

from __future__ import annotations

import json
from typing import Literal

from pydantic import BaseModel, ConfigDict

from scratchworld_dist.kinds.audit._plan import AuditBody
from scratchworld_dist.sweep import JobSpec
from workers.contract import JobResult
from workers.kinds.audit import AuditObservation, GraderCheck

Verdict = Literal[
    "killed",
    "equivalent",
    "hole",
    "outside_task",
    "survived",
    "passed",
    "brittle",
    "golden_passes",
    "golden_fails",
    "error",
]
"""A mutant is killed (a test failed: right); one that passes every test is equivalent (the golden's observable
trace in the tests' own run and in every run of the task's exploration), a hole (a run the task allows differs:
the tests pass a wrong program), outside the task (only runs with answers the instruction rules out differ), or
survived when it could not be traced; a refactoring passed (right) or was judged brittle (a test failed it); the
golden itself passes or fails (then its variants' verdicts measure nothing); error: no verdict (the evaluation
itself failed)."""


class AuditRow(BaseModel):
    """One variant and the grader's answer to it (a row of ``audits/``)."""

    model_config = ConfigDict(frozen=True)

    job_id: str
    attempt: int
    task_id: str
    variant: str
    """golden, mutant or refactoring."""

    operator: str
    variant_id: str
    target: str
    block_id: str
    description: str
    before: str
    """Pseudocode of the changed script(s) before the change, and after it."""
    after: str
    tests_passed: int
    tests_total: int
    failing_tests: str
    """The names of the tests that failed, as a JSON list."""

    verdict: str
    observed: str | None = None
    """For a misjudged variant: ``equivalent`` (its trace and the golden's are the same) or ``differs``."""

    evidence: str | None = None
    """The first observable difference from the golden, when there is one."""

    change: str | None = None
    """The change in stable words (``QUESTION: 'a' -> 'b'``): what an explained hole's ``input`` matches."""

    block_opcode: str | None = None
    """The changed block's opcode in the golden."""

    shown_by: str | None = None
    """The run that showed ``evidence``, as JSON: ``{run, seed, answers, stimulus}`` (``run``: ``tests`` or the
    exploration episode's name; ``stimulus``: the last one done before the difference)."""

    first_difference: str | None = None
    """``evidence`` as JSON: ``{frame, target, field, a, b, variable}``."""

    runs_compared: int | None = None
    """Runs whose traces were compared (the tests' own, then the exploration's episodes)."""

    vacuous: str | None = None
    """On the golden's row: ``never_starts`` or ``observes_nothing`` when the task's tests judge nothing."""

    grader: str | None = None
    """On the golden's row, as JSON: what the tests do with the golden (``GraderCheck``: started, threads, the
    fields they read, the fields the golden changes)."""

    stopped_at: str | None = None
    """The test that failed the mutant first, when its tests stopped there (``stop_at_first_kill``)."""

    tests_not_run: int | None = None
    """With ``stopped_at``: its tests after that one, not run (counted in neither ``tests_passed`` nor
    ``tests_total``)."""


def verdict_of(variant: str, result: JobResult) -> Verdict:
    if result.outcome == "error" or result.evaluation is None:
        return "error"
    failed = result.outcome == "failed"
    if variant == "golden":
        return "golden_fails" if failed else "golden_passes"
    if variant == "mutant":
        if failed:
            return "killed"
        if isinstance(result.detail, AuditObservation):
            observed = result.detail.observed
            return (
                "equivalent" if observed == "equivalent" else "outside_task" if observed == "outside_task" else "hole"
            )
        return "survived"
    return "brittle" if failed else "passed"


def audit_row(job: JobSpec, result: JobResult) -> AuditRow:
    body = job.body
    if not isinstance(body, AuditBody):
        raise ValueError(f"job {job.job_id} is not an audit job")
    tests = result.evaluation.tests if result.evaluation is not None else []
    observation = result.detail if isinstance(result.detail, AuditObservation) else None
    check = result.detail if isinstance(result.detail, GraderCheck) else None
    stopped = result.evaluation.stopped_early if result.evaluation is not None else None
    return AuditRow(
        job_id=job.job_id, attempt=result.attempt, task_id=job.task_id, variant=body.variant,
        operator=body.operator, variant_id=body.variant_id, target=body.target, block_id=body.block_id,
        description=body.description, before=body.before, after=body.after,
        tests_passed=sum(test.passed for test in tests), tests_total=len(tests),
        failing_tests=json.dumps([test.name for test in tests if not test.passed]),
        verdict=verdict_of(body.variant, result),
        observed=observation.observed if observation else None,
        evidence=observation.difference if observation else None,
        change=body.change, block_opcode=body.block_opcode,
        shown_by=observation.shown_by.model_dump_json() if observation and observation.shown_by else None,
        first_difference=json.dumps(observation.first) if observation and observation.first else None,
        runs_compared=observation.runs if observation else None,
        vacuous=check.vacuous if check else None,
        grader=check.model_dump_json(exclude={"kind"}) if check else None,
        stopped_at=stopped.test if stopped else None, tests_not_run=stopped.not_run if stopped else None,
    )  # fmt: skip
