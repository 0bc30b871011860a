"""One drag job: a recycled editor in the task's view, one observation, one answer, one real drag.

The result is an ordinary ``JobResult``: one step (the drag, with the model call booked on
it), one test (the expected connection, verified from the VM's blocks), and a ``DragAttempt``
with the points and their distances to the exact regions. Regions are computed once per task
and worker (the view, and so every pixel, is the same for each of the task's jobs); a task
whose regions are empty in this editor cannot be passed and is ``task_invalid``, never a
failure of the agent.
"""

from __future__ import annotations

import hashlib
import time

import workers.kinds.drag._page as page
from workers.agent_api import code_mismatch, is_privileged
from workers.agents import EpisodeModels
from workers.contract import (
    AgentUnavailableError,
    BridgeError,
    DragRegions,
    EditorError,
    EpisodeTimings,
    EvalResult,
    JobResult,
    LLMSettings,
    ModelCallError,
    ObservationSettings,
    ProjectFormatError,
    StepRecord,
    TestVerdict,
)
from workers.editor import Editor, EditorPool
from workers.kinds.drag._agents import DragAnswer, DragQuestion, drag_agent
from workers.kinds.drag._annotate import annotate
from workers.kinds.drag._contract import DragAttempt, DragPayload, DragSpec
from workers.kinds.drag._prompts import draw_start_marker
from workers.llm import ModelCache
from workers.primitive import PrimitiveObserver, region_ocr, settle


class DragRunner:
    """Runs drag jobs in editors of one pool, keeping each task's regions."""

    def __init__(self, pool: EditorPool) -> None:
        self.pool = pool
        self._regions: dict[str, DragRegions] = {}

    async def run(self, spec: DragSpec, payload: DragPayload) -> JobResult:
        started, clock = time.time(), time.perf_counter()
        timings = EpisodeTimings()
        try:
            agent = drag_agent(spec.agent)
        except AgentUnavailableError as exc:
            return _finish(JobResult.errored(spec, "agent_error", str(exc)), started, clock, timings)
        mismatch = code_mismatch(spec.agent, spec.agent_code, type(agent))
        if mismatch is not None:
            return _finish(JobResult.errored(spec, "harness_mismatch", mismatch), started, clock, timings)
        cache = ModelCache(spec.model_cache.dir) if spec.model_cache is not None else None
        models = EpisodeModels((spec.llm or LLMSettings()).retry, spec.seed, cache=cache)
        step = StepRecord(index=0, action="drag", ok=False)
        try:
            async with self.pool.editor() as editor:
                editor.uses += 1
                try:
                    await page.set_up(editor, payload)
                except ProjectFormatError as exc:
                    message = f"the task's initial project cannot be loaded: {exc}"
                    return _finish(JobResult.errored(spec, "task_invalid", message), started, clock, timings)
                regions, computed_s = await self._regions_of(editor, payload)
                if regions.start.empty or regions.end.empty:
                    which = "grabs the source" if regions.start.empty else "makes the connection"
                    message = f"drag task {payload.task_id}: no pixel of its view {which} in this editor"
                    return _finish(JobResult.errored(spec, "task_invalid", message), started, clock, timings)
                question = await _question(editor, spec, payload, regions, is_privileged(type(agent)))
                timings.setup_s = time.perf_counter() - clock
                answer = await agent.answer(question, spec.model, models)
                timings.agent_s = time.perf_counter() - clock - timings.setup_s
                step = models.drain().booked_on(_step(answer, question, timings.agent_s))
                connected, observed = False, f"no drag ({answer.parse}): {answer.detail}".rstrip(": ")
                if answer.parse == "ok" and answer.start is not None and answer.end is not None:
                    before = await page.block_ids(editor)
                    await page.drag(editor, answer.start, answer.end)
                    connected, observed = await page.verify(editor, payload, before)
                timings.evaluation_s = time.perf_counter() - clock - timings.setup_s - timings.agent_s
        except ModelCallError as exc:
            step = models.drain().booked_on(step.model_copy(update={"error_code": exc.error_class}))
            result = JobResult.errored(spec, exc.error_class, str(exc), steps=[step])
            return _finish(result.model_copy(update={"images": models.images}), started, clock, timings)
        except (EditorError, BridgeError) as exc:
            result = JobResult.errored(spec, "editor_failure", f"{type(exc).__name__}: {exc}", steps=[step])
            return _finish(result, started, clock, timings)
        attempt = _attempt(spec, answer, regions, question, connected, observed, computed_s)
        annotated = annotate(question.screenshot_png, regions, answer.start, answer.end)
        digest = hashlib.sha256(annotated).hexdigest()
        verdict = TestVerdict(
            name=f"{payload.connection.kind} connection to {payload.reference_opcode}",
            passed=connected,
            error=None if connected else observed,
        )
        evaluation = EvalResult(
            success=connected, passed=int(connected), total=1, psr=float(connected), tests=[verdict]
        )
        result = JobResult(
            job_id=spec.job_id,
            attempt=spec.attempt,
            outcome="passed" if connected else "failed",
            stop_reason="done",
            evaluation=evaluation,
            steps=[step],
            images={**models.images, digest: annotated},
            detail=attempt.model_copy(update={"annotated_sha256": digest}),
        )
        return _finish(result, started, clock, timings)

    async def _regions_of(self, editor: Editor, payload: DragPayload) -> tuple[DragRegions, float]:
        """The task's regions and the seconds spent on them now (0 when this worker knew them)."""
        digest = hashlib.sha256(payload.initial_project)
        digest.update(payload.model_dump_json(exclude={"initial_project"}).encode())
        key = digest.hexdigest()
        if key in self._regions:
            return self._regions[key], 0.0
        regions = await page.regions(editor, payload)
        self._regions[key] = regions
        # Computing them draws previews and stand-ins with events off and takes them down again; the
        # observation is made on a view set up anew all the same, as every later job of the task's is.
        await page.set_up(editor, payload)
        return regions, regions.computed_s


async def _question(
    editor: Editor, spec: DragSpec, payload: DragPayload, regions: DragRegions, privileged: bool
) -> DragQuestion:
    """The observation: the settled page's screenshot (marked under ``gt_start``) and, if asked, its element list;
    the regions for a privileged agent (the harness's scripted ones)."""
    element_text, centres = None, {}
    if spec.element_list:
        settings = spec.observation or ObservationSettings()
        observation = await PrimitiveObserver(settings, region_ocr(settings)).observe(editor)
        png, element_text = observation.screenshot_png, observation.text
        centres = {e.index: e.center for e in observation.elements}
    else:
        await settle(editor, page.SETTLE_MS)
        png = await editor.page.screenshot(type="png")
    gt_start = regions.fixed_start if spec.setting == "gt_start" else None
    if gt_start is not None:
        png = draw_start_marker(png, gt_start)
    return DragQuestion(
        task_id=payload.task_id,
        instruction=payload.instruction,
        setting=spec.setting,
        screenshot_png=png,
        seed=spec.seed,
        gt_start=gt_start,
        element_text=element_text,
        element_centres=centres,
        regions=regions if privileged else None,
    )


def _step(answer: DragAnswer, question: DragQuestion, latency_s: float) -> StepRecord:
    args = {} if answer.start is None or answer.end is None else {"start": list(answer.start), "end": list(answer.end)}
    return StepRecord(
        index=0,
        action="drag",
        args=args,
        ok=answer.parse == "ok",
        error_code=None if answer.parse == "ok" else answer.parse,
        error_message=answer.detail or None,
        latency_s=latency_s,
        data={"setting": question.setting, "gt_start": list(question.gt_start) if question.gt_start else None},
    )


def _attempt(
    spec: DragSpec,
    answer: DragAnswer,
    regions: DragRegions,
    question: DragQuestion,
    connected: bool,
    observed: str,
    computed_s: float,
) -> DragAttempt:
    """The drag's points measured against the regions; the release moved with the press first (the grip moves)."""
    fields: dict[str, object] = {}
    if answer.start is not None:
        fields["start_in_region"] = regions.start.contains(*answer.start)
        fields["start_error_px"] = regions.start.distance(*answer.start)
        if answer.end is not None:
            fixed = regions.fixed_start
            moved = (answer.end[0] + fixed[0] - answer.start[0], answer.end[1] + fixed[1] - answer.start[1])
            fields["end_in_region"] = regions.end.contains(*moved)
            fields["end_error_px"] = regions.end.distance(*moved)
    return DragAttempt(
        setting=spec.setting,
        parse=answer.parse,
        start=answer.start,
        end=answer.end,
        connected=connected,
        observed=observed,
        gt_start=question.gt_start,
        regions=regions,
        regions_s=computed_s,
        **fields,  # type: ignore[arg-type]
    )


def _finish(result: JobResult, started: float, clock: float, timings: EpisodeTimings) -> JobResult:
    timings.total_s = time.perf_counter() - clock
    return result.model_copy(update={"timings": timings, "started_at": started, "finished_at": time.time()})
