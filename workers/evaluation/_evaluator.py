"""Execution-based evaluation: a project, a script, a verdict.

Each evaluation loads the project into a clean VM (a fresh editor page, or a used one that
recycled clean, see ``workers.editor._pool``; never the page an agent edited) and runs the task's
script there with a hard timeout, on the real clock or in virtual time (``scratch-gui/clock.js``:
simulated time skips ahead, capped at the timeout). Whatever goes wrong with the project or the
script (corrupt .sb3, a script that throws, hangs or returns garbage) comes back as an
``EvalResult`` with a classified error; only a broken browser session raises.
"""

from __future__ import annotations

import asyncio
import json
import time
from typing import cast, get_args

from pydantic import JsonValue

from workers.contract import (
    BridgeError,
    EditorError,
    EpisodeTimings,
    EvalErrorKind,
    EvalResult,
    EvalTimings,
    EvaluationClock,
    EvaluationSpec,
    JobResult,
    ProjectFormatError,
    ProjectLimits,
    ProjectTooLargeError,
    TaskPayload,
    check_project,
    outcome_of,
    with_random_seed,
)
from workers.editor import BrowserSession, Editor, EditorPool
from workers.evaluation._early_stop import early_stop
from workers.evaluation._profiles import apply_profile
from workers.evaluation._report import ReportError, parse_report
from workers.evaluation._trace import (
    DEFAULT_TRACE_CHARS,
    MAX_TRACE_CHARS,
    MIN_TRACE_CHARS,
    ObservableTrace,
    TracedEvaluation,
)

UNSEEDED_DEFAULT = 0
"""The seed of an evaluation whose spec names none (a job's evaluations name theirs: ``evaluation_seed``)."""

KILL_GRACE_S = 5.0
"""Extra time past the in-page timeout before the page itself is killed (a synchronous hang)."""

VIRTUAL_WALL_FACTOR = 2.0
"""Wall seconds allowed per simulated second of timeout under the virtual clock, before the kill.

Virtual time usually runs several times faster than the wall clock, but a frame still costs real
CPU, so a project that fills every frame's work budget on a loaded machine can run slower.
"""


def wall_limit_s(timeout_s: float, clock: EvaluationClock) -> float:
    """Wall seconds after which a script that has not come back is taken to block the page."""
    return (timeout_s * VIRTUAL_WALL_FACTOR if clock == "virtual" else timeout_s) + KILL_GRACE_S


def project_refusal(project: bytes, limits: ProjectLimits, name: str | None = None) -> EvalResult | None:
    """Why no page may see ``project`` (not a project, or over ``limits``) as a failed evaluation, else None.

    ``name`` (e.g. the file the bytes came from) starts the message, so it names the culprit.
    """
    try:
        check_project(project, limits)
    except ProjectFormatError as exc:
        kind: EvalErrorKind = "project_too_large" if isinstance(exc, ProjectTooLargeError) else "project_invalid"
        return EvalResult.failure(kind, f"{name}: {exc}" if name else str(exc))
    return None


# Failures the page attributes to the project or the script; any other kind is our own fault.
_PAGE_KINDS: frozenset[str] = frozenset(get_args(EvalErrorKind)) - {"editor_failure"}


class Evaluator:
    """Runs evaluations in clean editors of one browser session; safe to use concurrently."""

    def __init__(self, session: BrowserSession, pool: EditorPool | None = None) -> None:
        """With a ``pool``, editors come from it (opened ahead of time, or reused once recycled clean)."""
        self.session = session
        self.pool = pool

    async def evaluate(self, project: bytes, spec: EvaluationSpec, limits: ProjectLimits | None = None) -> EvalResult:
        """The verdict on ``project``; one over ``limits`` (default: ``ProjectLimits()``) never reaches a page.
        A spec that names no seed draws ``Math.random`` from seed 0: no verdict comes from unseeded numbers."""
        result, _ = await self._evaluate(project, spec, limits, None)
        return result

    async def evaluate_traced(
        self,
        project: bytes,
        spec: EvaluationSpec,
        limits: ProjectLimits | None = None,
        *,
        random_seed: int | None = 0,
        max_chars: int = DEFAULT_TRACE_CHARS,
    ) -> TracedEvaluation:
        """The verdict on ``project`` and the observable trace of its run (``workers.evaluation._trace``).

        ``random_seed`` seeds the page's ``Math.random`` (None: as ``spec`` says), so that a golden and a
        variant traced with one seed draw the same numbers; ``max_chars`` caps the trace's JSON. Recording
        does not change the verdict (tests/workers/evaluation/test_observable_trace_verdicts.py).
        """
        if not MIN_TRACE_CHARS <= max_chars <= MAX_TRACE_CHARS:
            raise ValueError(f"max_chars must be from {MIN_TRACE_CHARS} to {MAX_TRACE_CHARS}, got {max_chars}")
        seeded = spec if random_seed is None else with_random_seed(spec, random_seed)
        result, recorded = await self._evaluate(project, seeded, limits, max_chars)
        trace, record_s = recorded or (None, None)
        return TracedEvaluation(result=result, trace=trace, record_s=record_s)

    async def _evaluate(
        self, project: bytes, spec: EvaluationSpec, limits: ProjectLimits | None, trace_chars: int | None
    ) -> tuple[EvalResult, tuple[ObservableTrace, float] | None]:
        started = time.perf_counter()
        if spec.perturbation is None:
            spec = with_random_seed(spec, UNSEEDED_DEFAULT)
        timings = EvalTimings()
        limits = limits or ProjectLimits()
        refusal = project_refusal(project, limits)
        if refusal is not None:
            refusal.timings.total_s = time.perf_counter() - started
            return refusal, None
        trace: tuple[ObservableTrace, float] | None = None
        try:
            async with (self.pool or self.session).editor(spec.page) as editor:
                timings.editor_ready_s = editor.ready_s if editor.uses == 0 else None
                result = await self._evaluate_in(editor, project, spec, limits, timings, trace_chars)
                if trace_chars is not None:
                    trace = await _taken_trace(editor)
        except EditorError as exc:
            result = EvalResult.failure("editor_failure", f"{type(exc).__name__}: {exc}", timings=timings)
        result.timings.total_s = time.perf_counter() - started
        return result, trace

    async def _evaluate_in(
        self,
        editor: Editor,
        project: bytes,
        spec: EvaluationSpec,
        limits: ProjectLimits,
        timings: EvalTimings,
        trace_chars: int | None,
    ) -> EvalResult:
        mouse = spec.perturbation.mouse if spec.perturbation else None
        conditions = await apply_profile(editor, spec.profile, mouse)  # before the project: it may read the mouse
        result = await self._load_and_run(editor, project, spec, limits, timings, trace_chars)
        result.conditions = conditions.model_copy(
            update={
                "clock": spec.clock,
                "render": spec.render,
                "page": spec.page,
                "timing": spec.timing if spec.clock == "virtual" else "real",
                "frame_lateness": spec.frame_lateness,
                "perturbation": spec.perturbation,
            }
        )
        return result

    async def _load_and_run(
        self,
        editor: Editor,
        project: bytes,
        spec: EvaluationSpec,
        limits: ProjectLimits,
        timings: EvalTimings,
        trace_chars: int | None,
    ) -> EvalResult:
        phase_start = time.perf_counter()
        try:
            await editor.load_project(project, limits)
        except BridgeError as exc:
            return EvalResult.failure(_kind(exc), exc.detail, timings=timings)
        timings.project_load_s = time.perf_counter() - phase_start

        console_start = len(editor.console)
        phase_start = time.perf_counter()
        result_json: str | None = None
        notes: dict[str, JsonValue] = {}
        limit_s = wall_limit_s(spec.timeout_s, spec.clock)
        try:
            running = editor.run_evaluation(spec, observable_trace_chars=trace_chars)
            run = await asyncio.wait_for(running, limit_s)
            result_json = run.result_json
            notes = run.notes
            timings.script_clock_s = run.duration_ms / 1000
        except TimeoutError:
            # The page is stuck in synchronous code; leaving the ``editor()`` block kills it.
            editor.reusable = False
            kind: EvalErrorKind = "script_timeout"
            message = f"{spec.script_name} blocked the page for over {limit_s:.0f} s and was killed"
        except BridgeError as exc:
            kind, message = _kind(exc), exc.detail
        timings.script_s = time.perf_counter() - phase_start
        console = editor.console[console_start:]
        if result_json is None:
            return EvalResult.failure(kind, message, console=console, timings=timings)

        try:
            report = parse_report(json.loads(result_json))
        except ReportError as exc:
            return EvalResult.failure("result_invalid", f"{spec.script_name}: {exc}", console=console, timings=timings)
        stopped = early_stop(report, notes.get("earlyStop"))
        return EvalResult(
            success=report.passed == report.total,
            passed=report.passed,
            total=report.total,
            psr=report.passed / report.total,
            tests=report.tests,
            warnings=report.warnings,
            console=console,
            timings=timings,
            stopped_early=stopped,
        )


async def _taken_trace(editor: Editor) -> tuple[ObservableTrace, float] | None:
    """The trace the page recorded and the real seconds recording took, if the page can still give them:
    a page killed for blocking cannot, and a trace lost to a broken page leaves the verdict as it was."""
    if not editor.reusable:
        return None
    try:
        value = await editor.take_observable_trace()
    except (BridgeError, EditorError):
        return None
    if not isinstance(value, dict):
        return None
    record_ms = value.get("recordMs")
    return ObservableTrace.model_validate(value), float(record_ms) / 1000 if isinstance(record_ms, int | float) else 0.0


def _kind(exc: BridgeError) -> EvalErrorKind:
    if exc.kind not in _PAGE_KINDS:
        raise EditorError(f"the bridge failed unexpectedly: {exc}") from exc
    return cast(EvalErrorKind, exc.kind)


async def judged(
    evaluator: Evaluator,
    project: bytes,
    task: TaskPayload,
    limits: ProjectLimits,
    job_id: str,
    attempt: int,
    stop_reason: str,
    *,
    random_seed: int,
) -> JobResult:
    """The verdict on ``project`` under ``task.evaluation`` as a job's result without steps (a regrade, an audit
    variant), made exactly as an episode's final project is judged, its ``Math.random`` drawn from
    ``random_seed``; ``stop_reason`` says what the job was."""
    started, clock = time.time(), time.perf_counter()
    evaluation = await evaluator.evaluate(project, with_random_seed(task.evaluation, random_seed), limits)
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
