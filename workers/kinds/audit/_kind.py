"""The ``audit`` kind as a worker runs it: the variant evaluated in the recycled evaluation editors, under the task's
profile and clock, exactly as an episode's final project (or a regrade) is. A variant the tests misjudge (a
mutant that passes, a refactoring that fails) is then compared with the golden by behaviour (``_judge``: the
tests' own run and the task's exploration); the golden's own job checks whether its tests judge anything at all
(``_vacuity``)."""

from __future__ import annotations

import json
from functools import lru_cache
from typing import TYPE_CHECKING

from pydantic import BaseModel

from workers.contract import JobResult, Sb3Archive, TaskPayload, WorkerJob
from workers.kinds._protocol import AgentGroup, WorkerHost
from workers.kinds.audit._contract import AuditSpec
from workers.kinds.audit._golden_runs import TRACE_SEED

if TYPE_CHECKING:
    from workers.evaluation import Evaluator

EVALUATED = "evaluated"
"""Stop reason of an audit job's result."""


class AuditKind:
    """Audit jobs: a variant of a task's golden project evaluated by the task's tests, no agent."""

    name = "audit"
    specs: tuple[type[BaseModel], ...] = (AuditSpec,)
    payloads: tuple[type[BaseModel], ...] = (TaskPayload,)
    code: tuple[str, ...] = ("kinds/audit/",)
    """This folder; the evaluation it runs is every kind's (core)."""

    needs_browser = True
    agents: AgentGroup | None = None
    """No agent acts: the variant is the project judged."""

    async def run(self, host: WorkerHost, spec: WorkerJob, payload: BaseModel) -> JobResult:
        if not (isinstance(spec, AuditSpec) and isinstance(payload, TaskPayload)):
            return JobResult.errored(spec, "internal_error", "an audit job needs its spec and its task's payload")
        if payload.golden_project is None:
            return JobResult.errored(spec, "task_invalid", f"task {payload.task_id} has no golden project to vary")
        browser = await host.browser()
        work = _audit(browser.evaluator, spec, payload, payload.golden_project)
        return await host.in_browser(spec, browser.session, work)


AUDIT = AuditKind()


async def _audit(evaluator: Evaluator, spec: AuditSpec, task: TaskPayload, golden: bytes) -> JobResult:
    from workers.evaluation import judged  # the browser stack, on the first job
    from workers.kinds.audit._judge import judged_by_behaviour
    from workers.kinds.audit._vacuity import grader_check

    project = _variant(golden, spec.project_json)
    judging = _stopping(task) if spec.stop_at_first_failure else task
    result = await judged(
        evaluator, project, judging, spec.project_limits, spec.job_id, spec.attempt, EVALUATED, random_seed=TRACE_SEED
    )
    limits, plan = spec.project_limits, spec.exploration
    if spec.variant == "golden":
        if result.outcome != "passed":
            return result  # its tests fail the golden: what they read says nothing of the variants
        check = await grader_check(evaluator, golden, task.evaluation, limits, plan)
        return result if check is None else result.model_copy(update={"detail": check})
    misjudged = (spec.variant == "mutant" and result.outcome == "passed") or (
        spec.variant == "refactoring" and result.outcome == "failed"
    )
    if not misjudged:
        return result
    observation = await judged_by_behaviour(evaluator, golden, project, task.evaluation, limits, plan)
    return result if observation is None else result.model_copy(update={"detail": observation})


def _stopping(task: TaskPayload) -> TaskPayload:
    """The task judged with its tests stopping at the first failure (its traces run every test)."""
    return task.model_copy(update={"evaluation": task.evaluation.model_copy(update={"stop_at_first_failure": True})})


@lru_cache(maxsize=8)
def _archive(golden: bytes) -> Sb3Archive:
    return Sb3Archive(golden)


def _variant(golden: bytes, project_json: str) -> bytes:
    """The golden's assets with the variant's project.json (its archive kept for the task's next variants)."""
    return _archive(golden).with_project(json.loads(project_json))
