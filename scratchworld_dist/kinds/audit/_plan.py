"""Planning an audit: its section of a sweep config (``audit:``: how many variants of each golden, from which
seed, the declarations of an upstream clone), and each selected task's golden project and its variants (mutants
and refactorings), one job each, with the task's exploration plan (``_exploration``)."""

from __future__ import annotations

import hashlib
import json
import re
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import Any, ClassVar

from pydantic import BaseModel, ConfigDict, Field

from scratchworld_dist._errors import SuiteError
from scratchworld_dist.kinds.audit._declarations import TaskDeclarations
from scratchworld_dist.kinds.audit._exploration import exploration_plan
from scratchworld_dist.kinds.audit.variants import (
    Mutant,
    ProgramFormatError,
    Refactoring,
    enumerate_mutants,
    enumerate_refactorings,
    sample_mutants,
    sample_refactorings,
)
from scratchworld_dist.kinds.tasks import TaskContent
from scratchworld_dist.sweep import JobBody, JobSpec, SweepConfig, identity_id
from workers.contract import AgentRef, ProjectLimits, ScratchWorldError, check_project
from workers.kinds.audit import ExplorationPlan, VariantKind

DEFAULT_AGENT = AgentRef(name="oracle")
"""The config's default agent: the audit runs none, so it takes no other."""


class AuditBody(JobBody):
    """One variant of a task's golden project: what it changed, where, and its project.json."""

    kind: str = "audit"
    variant: VariantKind
    variant_id: str
    operator: str
    target: str
    block_id: str
    description: str
    before: str
    after: str
    project_json: str
    """The variant's project.json (compact); the worker gets the golden's assets with it."""

    change: str = ""
    """The change in stable words (``QUESTION: 'a' -> 'b'``)."""

    block_opcode: str = ""
    """The changed block's opcode in the golden ('' for a renamed variable or list, whose id ``block_id`` is)."""

    exploration: ExplorationPlan | None = None
    """The task's exploration plan (the same for every job of the task; part of each one's identity)."""

    stop_at_first_failure: bool = False
    """Its tests stop at the first that fails it (``EvaluationSpec.stop_at_first_failure``): a mutant's, unless
    the section says ``stop_at_first_kill: false``."""

    def columns(self) -> dict[str, Any]:
        return {"mode": self.variant, "max_steps": 0}


def evaluated_under(config: SweepConfig) -> SweepConfig:
    """The config its variants are evaluated under: on the virtual clock unless it names one (a suite's
    real-clock default would make verdicts depend on the machine's load, and a grader's strength is a property of
    its tests)."""
    return config if config.clock is not None else config.model_copy(update={"clock": "virtual"})


def golden_json(content: TaskContent, limits: ProjectLimits | None = None) -> dict[str, Any]:
    """The task's golden project.json, read as a worker checks a project (``SuiteError`` when it has none or
    it is not one)."""
    data = content.payload.golden_project
    where = content.task.golden_project
    if data is None:
        raise SuiteError(f"task {content.task.id} has no golden project to audit", where)
    try:
        return check_project(data, limits)
    except ScratchWorldError as exc:  # ProjectFormatError, ProjectTooLargeError
        raise SuiteError(f"task {content.task.id}: the golden project cannot be read ({exc})", where) from exc


def task_variants(
    content: TaskContent, settings: AuditSweep, limits: ProjectLimits | None = None
) -> list[Mutant | Refactoring]:
    """The variants of one task's golden the section asks for: mutants, then refactorings."""
    return _variants(golden_json(content, limits), content, settings)


def _variants(project: dict[str, Any], content: TaskContent, settings: AuditSweep) -> list[Mutant | Refactoring]:
    """``task_variants`` of the golden ``project`` already read."""
    try:
        mutants = (
            enumerate_mutants(project)
            if settings.mutants_per_task is None
            else sample_mutants(project, settings.mutants_per_task, f"{settings.seed}:{content.task.id}")
        )
        refactorings = (
            enumerate_refactorings(project)
            if settings.refactorings_per_task is None
            else sample_refactorings(project, settings.refactorings_per_task, f"{settings.seed}:{content.task.id}")
        )
    except ProgramFormatError as exc:
        raise SuiteError(f"task {content.task.id}: the golden cannot be audited: {exc}") from exc
    named = [r for r in refactorings if not _renames_a_required_name(r, content.payload.instruction)]
    return [*mutants, *named]


def _renames_a_required_name(refactoring: Refactoring, instruction: str) -> bool:
    """Whether it renames a variable or list the task's instruction names: that name is then part of the task
    (a grader that finds it by name is right), so the rename is no behaviour-preserving rewrite."""
    if not refactoring.operator.startswith("rename_"):
        return False
    old = refactoring.change.split(" -> ", 1)[0]
    return re.search(rf"(?<!\w){re.escape(old)}(?!\w)", instruction, re.IGNORECASE) is not None


def audit_jobs(
    contents: list[TaskContent],
    settings: AuditSweep,
    agent: AgentRef,
    harness: str,
    limits: ProjectLimits | None = None,
    declarations: Mapping[str, TaskDeclarations] | None = None,
) -> Iterator[JobSpec]:
    """The golden of each task, then one job per variant: named by its project, its task, its exploration plan
    (``declarations``: the tasks' answer domains) and the harness (not by the seed that picked it: the same
    variant picked again is the same job)."""
    for content in contents:
        golden = golden_json(content, limits)
        declared = (declarations or {}).get(content.task.id)
        plan = exploration_plan(
            golden,
            content.payload.instruction,
            declared.answers if declared else None,
            declared.source if declared else "",
        )
        unchanged = AuditBody(
            variant="golden", variant_id="golden", operator="golden", target="", block_id="",
            description="the golden project, unchanged", before="", after="", project_json=_text(golden),
            exploration=plan,
        )  # fmt: skip
        yield _job(content, unchanged, agent, harness, limits)
        for variant in _variants(golden, content, settings):
            mutant = isinstance(variant, Mutant)
            body = AuditBody(
                variant="mutant" if mutant else "refactoring",
                variant_id=variant.mutant_id if isinstance(variant, Mutant) else variant.refactoring_id,
                operator=variant.operator, target=variant.target, block_id=variant.block_id,
                description=variant.description, before=variant.before, after=variant.after,
                project_json=_text(variant.project), change=variant.change,
                block_opcode=_opcode(golden, variant.target, variant.block_id), exploration=plan,
                stop_at_first_failure=mutant and settings.stop_at_first_kill,
            )  # fmt: skip
            yield _job(content, body, agent, harness, limits)


def _opcode(project: dict[str, Any], target: str, block_id: str) -> str:
    for candidate in project.get("targets", []):
        if isinstance(candidate, dict) and candidate.get("name") == target:
            block = (candidate.get("blocks") or {}).get(block_id)
            return str(block.get("opcode", "")) if isinstance(block, dict) else ""
    return ""


def _text(project: dict[str, Any]) -> str:
    return json.dumps(project, separators=(",", ":"), sort_keys=True)


def _job(content: TaskContent, body: AuditBody, agent: AgentRef, harness: str, limits: ProjectLimits | None) -> JobSpec:
    digest = hashlib.sha256(body.project_json.encode()).hexdigest()
    identity: dict[str, Any] = {"audit": body.variant, "project": digest, "task": content.task_hash, "harness": harness}
    if limits is not None and limits != ProjectLimits():  # a project over them is refused: another verdict
        identity["project_limits"] = limits.model_dump(mode="json")
    if body.exploration is not None:  # what decides equivalence and vacuity besides the tests
        identity["exploration"] = body.exploration.model_dump(mode="json", exclude={"domain_source"})
    if body.stop_at_first_failure:  # its verdict is the same, its row names fewer tests
        identity["tests"] = "to the first failure"
    return JobSpec(
        job_id=identity_id(identity), model=None, agent=agent, task_id=content.task.id,
        category=content.task.category, task_hash=content.task_hash, seed=0, harness=harness, body=body,
    )  # fmt: skip


class AuditSweep(BaseModel):
    """Which mutants and refactorings of each task's golden project are evaluated."""

    model_config = ConfigDict(extra="forbid")

    mutants_per_task: int | None = Field(default=None, gt=0)
    """At most this many mutants per task, spread over the operators (None: every one)."""

    refactorings_per_task: int | None = Field(default=None, ge=0)
    """At most this many refactorings per task (None: every one; 0: none)."""

    seed: int = 0
    """Which mutants and refactorings a cap picks (the same seed picks the same ones)."""

    explanations: Path | None = None
    """One file of declarations for every task (an upstream clone's: ``_declarations``); None: each task's own
    ``audit.yaml`` in our layout, the shipped file for an upstream clone."""

    resume_free: ClassVar[dict[str, Any]] = {"explanations": True}
    """The file may change between sessions: what it decides (answer domains) is in each job's identity, and
    explained holes are the report's."""

    stop_at_first_kill: bool = True
    """A mutant's tests stop at the first that fails it: a killed mutant needs no more, and one that fails by
    waiting out its tests' timeouts (a loop that never ends) costs one timeout instead of all. Its row names that
    test (``stopped_at``); the report's per-test figures then count, for each mutant, the test that killed it first.
    False: every test of every mutant runs. Goldens and refactorings always run every test."""
