"""Suite validation: every golden must pass, every debug initial must fail.

A task is adversarially valid when its golden project passes all tests and its initial project
does not (for debug tasks the initial must fail; for the others, passing every test from the
start would make the task meaningless, so it is flagged too).
"""

from __future__ import annotations

import asyncio
from collections.abc import Callable
from typing import TYPE_CHECKING, Literal

from pydantic import BaseModel

from scratchworld_dist.suites import SuiteStability, Task
from workers.contract import (
    EvalResult,
    EvaluationClock,
    EvaluationPage,
    EvaluationProfile,
    EvaluationRender,
    EvaluationSpec,
    EvaluationTiming,
)

if TYPE_CHECKING:
    from workers.editor import BrowserConfig

Which = Literal["golden", "initial"]


class ProjectCheck(BaseModel):
    """One project of a task, evaluated."""

    success: bool
    passed: int
    total: int
    psr: float
    error: str | None
    """``kind: message`` when the evaluation produced no report."""
    wall_s: float
    failed_tests: list[str] = []
    """The names of the tests that did not pass."""
    random_seed: int | None = None
    """The seed the evaluation drew ``Math.random`` from (``validate --seed``: the task's jobs' at that seed)."""

    @classmethod
    def of(cls, result: EvalResult) -> ProjectCheck:
        return cls(
            success=result.success,
            passed=result.passed,
            total=result.total,
            psr=result.psr,
            error=f"{result.error.kind}: {result.error.message}" if result.error else None,
            wall_s=round(result.timings.total_s, 3),
            failed_tests=[test.name for test in result.tests if not test.passed],
            random_seed=result.random_seed,
        )


class TaskValidation(BaseModel):
    """The validation row of one task."""

    task_id: str
    category: str
    golden: ProjectCheck | None
    """None when the suite has no golden for the task."""
    initial: ProjectCheck
    unstable_tests: dict[str, str] | None = None
    """The task's tests known to be unstable, each with its note ({} when none is); None when the suite's
    known test stability does not cover the task (see ``scratchworld_dist.suites.known_stability``)."""

    def _fails_only_unstable(self, check: ProjectCheck) -> bool:
        failed = check.failed_tests
        return check.error is None and bool(failed) and all(name in (self.unstable_tests or {}) for name in failed)

    def failures(self) -> list[str]:
        """Reasons that make the suite invalid (a golden failing only unstable tests is a warning instead)."""
        reasons = []
        if self.golden is not None and not self.golden.success and not self._fails_only_unstable(self.golden):
            reasons.append("golden does not pass")
        if self.category == "debug" and self.initial.success:
            reasons.append("debug initial already passes")
        return reasons

    def warnings(self) -> list[str]:
        reasons = []
        if self.golden is not None and not self.golden.success and self._fails_only_unstable(self.golden):
            names = ", ".join(repr(name) for name in self.golden.failed_tests)
            reasons.append(f"golden fails only unstable test(s) {names}")
        if self.golden is None:
            reasons.append("no golden project")
        if self.category != "debug" and self.initial.success:
            reasons.append("initial already passes every test")
        return reasons


async def validate_tasks(
    tasks: list[Task],
    *,
    parallel: int = 1,
    browser: BrowserConfig | None = None,
    on_evaluated: Callable[[Task, Which, EvalResult], None] | None = None,
    profile: EvaluationProfile | None = None,
    clock: EvaluationClock | None = None,
    render: EvaluationRender | None = None,
    timing: EvaluationTiming | None = None,
    page: EvaluationPage | None = None,
    stability: SuiteStability | None = None,
    seed: int = 0,
) -> list[TaskValidation]:
    """Evaluate each task's golden and initial project, ``parallel`` pages at a time, drawing random numbers
    as the task's jobs at sweep ``seed`` do (so a rerun repeats every verdict).

    ``profile``, ``clock``, ``render``, ``timing`` and ``page`` override each task's defaults;
    ``stability``, the suite's known test stability, marks the rows' unstable tests.
    """
    if parallel < 1:
        raise ValueError("parallel must be at least 1")
    # The browser stack loads here, not with the package: reports and status never need it.
    from workers.editor import BrowserSession, EditorPool
    from workers.evaluation import Evaluator

    slots = asyncio.Semaphore(parallel)
    # Editors are recycled after each evaluation. No spare is opened ahead: it would cost a whole
    # editor's start-up for every command, to save its wait only when a page cannot be recycled.
    async with BrowserSession(browser) as session, EditorPool(session, spare=0) as pool:
        evaluator = Evaluator(session, pool)

        async def run(task: Task, which: Which, project: bytes, spec: EvaluationSpec) -> EvalResult:
            async with slots:
                result = await evaluator.evaluate(project, spec)
            if on_evaluated is not None:
                on_evaluated(task, which, result)
            return result

        async with asyncio.TaskGroup() as group:
            pending = []
            for task in tasks:
                # Files are read here, before the evaluations start; the script and helper once per task.
                spec = task.evaluation_spec(profile, clock, render, timing, page=page, seed=seed)
                golden_path = task.golden_project
                golden = group.create_task(run(task, "golden", golden_path.read_bytes(), spec)) if golden_path else None
                initial = group.create_task(run(task, "initial", task.initial_project.read_bytes(), spec))
                pending.append((task, golden, initial))

    rows = []
    for task, golden, initial in pending:
        rows.append(
            TaskValidation(
                task_id=task.id,
                category=task.category,
                golden=ProjectCheck.of(golden.result()) if golden else None,
                initial=ProjectCheck.of(initial.result()),
                unstable_tests=stability.unstable_notes(task) if stability else None,
            )
        )
    return rows
