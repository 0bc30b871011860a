"""One perception job: one answer to one item, scored both ways. No editor: the screenshot is static.

The result is an ordinary ``JobResult``: one step (the answer, with the model call booked on it),
one test ("the answer is right", by the normalized scoring, which decides ``passed``/``failed``), and a
``PerceptionAttempt`` with the reply and both scores. A model call that fails for good is an error with
its class, never a wrong answer: it has no verdict and reports count it under coverage. The item's
screenshot is stored once per run by the driver, so it is left out of the result's images.
"""

from __future__ import annotations

import hashlib
import time

from workers.agent_api import code_mismatch, is_privileged
from workers.agents import EpisodeModels
from workers.contract import (
    AgentUnavailableError,
    EpisodeTimings,
    EvalResult,
    JobResult,
    LLMSettings,
    ModelCallError,
    StepRecord,
    TestVerdict,
)
from workers.kinds.perception._agents import PerceptionQuestion, perception_agent
from workers.kinds.perception._contract import PerceptionAttempt, PerceptionPayload, PerceptionSpec
from workers.kinds.perception._scoring import score_reply
from workers.llm import ModelCache


async def run_perception(spec: PerceptionSpec, payload: PerceptionPayload) -> JobResult:
    """Ask ``spec``'s agent ``payload``'s question and score the answer (never raises for a model failure)."""
    started, clock = time.time(), time.perf_counter()
    timings = EpisodeTimings()
    screenshot = hashlib.sha256(payload.screenshot_png).hexdigest()
    try:
        agent = perception_agent(spec.agent)
    except AgentUnavailableError as exc:
        return _finish(JobResult.errored(spec, "agent_error", str(exc)), started, clock, timings)
    mismatch = code_mismatch(spec.agent, spec.agent_code, type(agent))
    if mismatch is not None:
        return _finish(JobResult.errored(spec, "harness_mismatch", mismatch), started, clock, timings)
    cache = ModelCache(spec.model_cache.dir) if spec.model_cache is not None else None
    models = EpisodeModels((spec.llm or LLMSettings()).retry, spec.seed, cache=cache)
    question = PerceptionQuestion(
        item_id=payload.item_id,
        question=payload.question,
        answer_format=payload.answer_format,
        value_kind=payload.value_kind,
        screenshot_png=payload.screenshot_png,
        label=payload.answer if is_privileged(type(agent)) else None,
    )
    try:
        reply = await agent.answer(question, spec.model, models)
    except ModelCallError as exc:
        step = models.drain().booked_on(StepRecord(index=0, action="answer", ok=False, error_code=exc.error_class))
        result = JobResult.errored(spec, exc.error_class, str(exc), steps=[step])
        return _finish(_shared_image_dropped(result, models, screenshot), started, clock, timings)
    except AgentUnavailableError as exc:
        return _finish(JobResult.errored(spec, "agent_error", str(exc)), started, clock, timings)
    timings.agent_s = time.perf_counter() - clock
    score = score_reply(reply, payload.answer, payload.answer_format, payload.value_kind)
    step = StepRecord(
        index=0,
        action="answer",
        args={"answer": score.extracted},
        ok=score.parse == "ok",
        error_code=None if score.parse == "ok" else score.parse,
        latency_s=timings.agent_s,
        data={"strict": score.strict, "normalized": score.normalized},
    )
    step = models.drain().booked_on(step)
    if not agent.needs_model:  # a scripted answer is the step's reply too, so every row shows what was said
        step = step.model_copy(update={"reply": reply})
    verdict = TestVerdict(
        name=f"{payload.kind} item {payload.item_id}",
        passed=score.normalized,
        error=None if score.normalized else f"expected {payload.answer!r}, read {score.extracted!r} ({score.parse})",
    )
    evaluation = EvalResult(
        success=score.normalized, passed=int(score.normalized), total=1, psr=float(score.normalized), tests=[verdict]
    )
    result = JobResult(
        job_id=spec.job_id,
        attempt=spec.attempt,
        outcome="passed" if score.normalized else "failed",
        stop_reason="done",
        evaluation=evaluation,
        steps=[step],
        detail=PerceptionAttempt(reply=reply, expected=payload.answer, score=score, screenshot_sha256=screenshot),
    )
    return _finish(_shared_image_dropped(result, models, screenshot), started, clock, timings)


def _shared_image_dropped(result: JobResult, models: EpisodeModels, screenshot: str) -> JobResult:
    """The result with the prompts' images but the item's screenshot, which the run keeps once for all jobs."""
    images = {digest: data for digest, data in models.images.items() if digest != screenshot}
    return result.model_copy(update={"images": images})


def _finish(result: JobResult, started: float, clock: float, timings: EpisodeTimings) -> JobResult:
    timings.total_s = time.perf_counter() - clock
    return result.model_copy(update={"timings": timings, "started_at": started, "finished_at": time.time()})
