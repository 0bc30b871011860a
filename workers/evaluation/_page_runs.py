"""Runs of a project that judge the grader rather than the project: a task's tests run while the page notes what
they read (``scratch-gui/trace/reads.js``), and an exploration of the program that no test drives (the page's
``explore`` runner, ``scratch-gui/explore/``). Both run as an evaluation does (a clean page, the spec's profile,
clock, render and seed, the observable trace recorded), and both give a trace and what the page noted, never a
verdict: the grader audit (``workers.kinds.audit``) compares them with the golden's.
"""

from __future__ import annotations

import asyncio
import json
import time

from pydantic import BaseModel, ConfigDict, Field, JsonValue

from workers.contract import BridgeError, EditorError, EvaluationSpec, ProjectLimits, with_random_seed
from workers.editor import Editor
from workers.evaluation._evaluator import Evaluator, project_refusal, wall_limit_s
from workers.evaluation._profiles import apply_profile
from workers.evaluation._trace import DEFAULT_TRACE_CHARS, ObservableTrace

EXPLORE_RUNNER = "explore"
"""The page's exploration runner (``scratch-gui/explore/run.js``)."""


class ObservedReads(BaseModel):
    """What a task's tests looked at while they ran (``scratch-gui/trace/reads.js``)."""

    model_config = ConfigDict(frozen=True)

    flags: int = Field(ge=0)
    """Green flags the tests clicked."""

    threads: int = Field(ge=0)
    """Scripts the tests started from outside a VM step (the flag, keys, clicks, broadcasts they send)."""

    reads: list[tuple[str, str]]
    """(target, field) pairs of the observable trace the tests read: a sprite by name (clones fold into it),
    ``Stage``, or ``*`` for any (a listener to bubbles, questions, clones); a variable as ``var:<id>``."""

    events: list[str] = Field(default_factory=list)
    """VM events the tests listened to (``SAY``, ``QUESTION``, ``targetWasCreated``...)."""

    @property
    def started(self) -> bool:
        """Whether the tests started the program at all (a flag clicked, or a script started)."""
        return self.flags > 0 or self.threads > 0


class PageRun(BaseModel):
    """One such run: its observable trace, what the page's runner returned, what the tests read."""

    trace: ObservableTrace | None = None
    """None when there was no run to record (a refused project, a page killed for blocking)."""

    outcome: JsonValue = None
    """What the runner returned (an exploration: the answers it gave, when it did each stimulus)."""

    reads: ObservedReads | None = None
    error: str | None = None
    """Why the run did not finish (the trace, if any, is as far as it went)."""

    seconds: float = 0.0


async def explored(
    evaluator: Evaluator,
    project: bytes,
    spec: EvaluationSpec,
    timeline: dict[str, JsonValue],
    seed: int,
    limits: ProjectLimits | None = None,
    max_chars: int = DEFAULT_TRACE_CHARS,
) -> PageRun:
    """``project`` explored by the page's ``explore`` runner along ``timeline`` (its arguments: stimuli,
    answers, span), under ``spec``'s conditions and ``Math.random`` seeded with ``seed``; ``spec``'s timeout
    caps the run in simulated seconds."""
    runner: dict[str, JsonValue] = {"name": EXPLORE_RUNNER, "args": timeline}
    return await _run(evaluator, project, with_random_seed(spec, seed), limits, max_chars, runner=runner)


async def observed_tests_run(
    evaluator: Evaluator,
    project: bytes,
    spec: EvaluationSpec,
    seed: int,
    limits: ProjectLimits | None = None,
    max_chars: int = DEFAULT_TRACE_CHARS,
) -> PageRun:
    """The task's tests run on ``project`` as ``evaluate_traced`` runs them (the same trace under ``seed``),
    noting what they read and whether they start the program."""
    return await _run(evaluator, project, with_random_seed(spec, seed), limits, max_chars, observe_reads=True)


async def _run(
    evaluator: Evaluator,
    project: bytes,
    spec: EvaluationSpec,
    limits: ProjectLimits | None,
    max_chars: int,
    *,
    runner: dict[str, JsonValue] | None = None,
    observe_reads: bool = False,
) -> PageRun:
    started = time.perf_counter()
    limits = limits or ProjectLimits()
    refusal = project_refusal(project, limits)
    if refusal is not None:
        return PageRun(error=refusal.error.message if refusal.error else "refused")
    try:
        async with (evaluator.pool or evaluator.session).editor(spec.page) as editor:
            run = await _in(editor, project, spec, limits, max_chars, runner, observe_reads)
    except EditorError as exc:
        run = PageRun(error=f"{type(exc).__name__}: {exc}")
    return run.model_copy(update={"seconds": time.perf_counter() - started})


async def _in(
    editor: Editor,
    project: bytes,
    spec: EvaluationSpec,
    limits: ProjectLimits,
    max_chars: int,
    runner: dict[str, JsonValue] | None,
    observe_reads: bool,
) -> PageRun:
    await apply_profile(editor, spec.profile, spec.perturbation.mouse if spec.perturbation else None)
    try:
        await editor.load_project(project, limits)
    except BridgeError as exc:
        return PageRun(error=exc.detail)
    outcome: JsonValue = None
    error: str | None = None
    limit_s = wall_limit_s(spec.timeout_s, spec.clock)
    try:
        running = editor.run_evaluation(
            spec, observable_trace_chars=max_chars, runner=runner, observe_reads=observe_reads
        )
        done = await asyncio.wait_for(running, limit_s)
        outcome = json.loads(done.result_json) if runner is not None else None
    except TimeoutError:
        editor.reusable = False  # leaving the editor kills the page
        return PageRun(error=f"the run blocked the page for over {limit_s:.0f} s and was killed")
    except BridgeError as exc:
        error = exc.detail
    trace, reads = await _taken(editor, observe_reads)
    return PageRun(trace=trace, outcome=outcome, reads=reads, error=error)


async def _taken(editor: Editor, observe_reads: bool) -> tuple[ObservableTrace | None, ObservedReads | None]:
    """The trace (and the reads) the page recorded, if it can still give them."""
    try:
        trace = await editor.take_observable_trace()
        reads = await editor.take_observed_reads() if observe_reads else None
    except (BridgeError, EditorError):
        return None, None
    return (
        ObservableTrace.model_validate(trace) if isinstance(trace, dict) else None,
        ObservedReads.model_validate(reads) if isinstance(reads, dict) else None,
    )
