"""Running a flake plan: every golden and initial of the chosen tasks under every variant."""

from __future__ import annotations

import asyncio
from collections.abc import Callable
from typing import TYPE_CHECKING

from pydantic import BaseModel

from scratchworld_dist._validation import Which
from scratchworld_dist.kinds.tasks.flakes._load import cpu_load, load_average
from scratchworld_dist.kinds.tasks.flakes._plan import Variant
from scratchworld_dist.suites import Task
from workers.contract import EvalResult, EvaluationPage, EvaluationProfile, EvaluationSpec, calibrated_frame_lateness

if TYPE_CHECKING:
    from workers.editor import BrowserConfig

ERROR_VERDICT = "error"


class FlakeRun(BaseModel):
    """One evaluation of a flake run: which project, under what, and the verdict of each test."""

    task_id: str
    category: str
    which: Which
    variant: Variant
    verdicts: dict[str, bool]
    """Each reported test's verdict, by test name (empty when the evaluation failed)."""
    error: str | None
    """``kind: message`` when the evaluation produced no report."""
    load_average: float
    """The machine's one-minute load average when the run ended."""
    wall_s: float

    @classmethod
    def of(cls, task: Task, which: Which, variant: Variant, result: EvalResult) -> FlakeRun:
        return cls(
            task_id=task.id,
            category=task.category,
            which=which,
            variant=variant,
            verdicts={test.name: test.passed for test in result.tests},
            error=f"{result.error.kind}: {result.error.message}" if result.error else None,
            load_average=load_average(),
            wall_s=round(result.timings.total_s, 3),
        )


def variant_spec(base: EvaluationSpec, variant: Variant) -> EvaluationSpec:
    """The task's spec under ``variant`` (validated: phase and lateness need the virtual clock)."""
    fields = base.model_dump()
    fields.update(
        clock=variant.clock,
        render=variant.render,
        perturbation=variant.perturbation,
        timing=variant.timing,
        frame_lateness=calibrated_frame_lateness() if variant.timing == "calibrated" else None,
    )
    return EvaluationSpec.model_validate(fields)


async def run_flakes(
    tasks: list[Task],
    variants: list[Variant],
    *,
    profile: EvaluationProfile | None = None,
    page: EvaluationPage | None = None,
    parallel: int = 1,
    browser: BrowserConfig | None = None,
    on_run: Callable[[FlakeRun], None] | None = None,
) -> list[FlakeRun]:
    """Evaluate each task's golden (if any) and initial under each variant, ``parallel`` editors at a time.

    Runs without CPU load come first; the busy processes run only during the load variants.
    ``variants`` hold the clock and render of each run (see ``plan_variants``).
    """
    if parallel < 1:
        raise ValueError("parallel must be at least 1")
    from workers.editor import BrowserSession, EditorPool  # the browser stack loads only here
    from workers.evaluation import Evaluator

    jobs: list[tuple[Task, Which, bytes, EvaluationSpec]] = []
    for task in tasks:  # files are read before any evaluation starts
        base = task.evaluation_spec(profile, page=page)
        projects: list[tuple[Which, bytes]] = [("initial", task.initial_project.read_bytes())]
        if task.golden_project:
            projects.insert(0, ("golden", task.golden_project.read_bytes()))
        jobs.extend((task, which, project, base) for which, project in projects)

    slots = asyncio.Semaphore(parallel)
    runs: list[FlakeRun] = []
    # No spare ahead (as in ``validate``): a page that cannot be recycled is replaced when needed.
    async with BrowserSession(browser) as session, EditorPool(session, spare=0) as pool:
        evaluator = Evaluator(session, pool)

        async def run(task: Task, which: Which, project: bytes, spec: EvaluationSpec, variant: Variant) -> None:
            async with slots:
                result = await evaluator.evaluate(project, variant_spec(spec, variant))
            done = FlakeRun.of(task, which, variant, result)
            runs.append(done)
            if on_run is not None:
                on_run(done)

        for load in sorted({variant.cpu_load for variant in variants}):
            with cpu_load(load):
                async with asyncio.TaskGroup() as group:
                    for task, which, project, spec in jobs:
                        for variant in variants:
                            if variant.cpu_load == load:
                                group.create_task(run(task, which, project, spec, variant))
    order = {(task.id, which): index for index, (task, which, _, _) in enumerate(jobs)}
    position = {variant: index for index, variant in enumerate(variants)}
    return sorted(runs, key=lambda r: (order[(r.task_id, r.which)], position[r.variant]))
