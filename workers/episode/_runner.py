"""One episode: open the editor on the initial project, let the agent act, evaluate what it left.

The agent works in its own fresh page; the evaluation runs in another, clean page (``Evaluator``:
fresh, or with an ``EditorPool`` recycled after an earlier evaluation and verified clean), so
nothing the agent left running in its VM can influence the verdict.
"""

from __future__ import annotations

import json
import time

from pydantic import JsonValue

from workers.agents import Agent, ConversingAgent, NeedsEditor
from workers.contract import (
    FINAL_ACTIONS,
    Action,
    BridgeError,
    CompositeAction,
    EditorError,
    EpisodeResult,
    EpisodeSpec,
    EpisodeTimings,
    InvalidReply,
    LoadProject,
    ObservationSettings,
    PrimitiveAction,
    ProjectFormatError,
    ProjectLimits,
    ProjectTooLargeError,
    StepRecord,
    TaskPayload,
    outcome_of,
)
from workers.editor import BrowserSession, Editor, EditorPool
from workers.episode._environment import CompositeEnvironment, Environment, PrimitiveEnvironment
from workers.evaluation import Evaluator
from workers.llm import ModelCallError
from workers.ocr import RegionOCR
from workers.primitive import PrimitiveObserver, region_ocr

MAX_LOGGED_ARGS = 16_384
"""Arguments longer than this (as JSON characters) are logged by size: no action accepts that much
(the longest value any takes is 10,000 characters), and a runaway payload would fill every row and file."""

PRIMITIVE_STAGE = "small"
"""Primitive episodes show the small stage, like the upstream harness (more room for blocks)."""


class AgentCrashedError(Exception):
    """The agent raised instead of returning an action."""


class EpisodeRunner:
    """Runs episodes in one browser session; safe to use for several episodes at once."""

    def __init__(self, session: BrowserSession, evaluation_pool: EditorPool | None = None) -> None:
        """With an ``evaluation_pool``, evaluation pages are reused (it closes with the session)."""
        self.session = session
        self.evaluator = Evaluator(session, evaluation_pool)
        self._ocr: dict[ObservationSettings, RegionOCR | None] = {}
        """One OCR engine (and region cache) per setting, shared by this runner's episodes."""

    async def _environment(self, spec: EpisodeSpec, editor: Editor) -> Environment:
        if spec.mode == "composite":
            return CompositeEnvironment(editor)
        await editor.set_stage_size(PRIMITIVE_STAGE)
        settings = spec.observation or ObservationSettings()
        if settings not in self._ocr:
            self._ocr[settings] = region_ocr(settings)
        return PrimitiveEnvironment(editor, PrimitiveObserver(settings, self._ocr[settings]))

    async def run(self, spec: EpisodeSpec, task: TaskPayload, agent: Agent) -> EpisodeResult:
        started, clock = time.time(), time.perf_counter()
        timings = EpisodeTimings()
        steps: list[StepRecord] = []
        try:
            async with self.session.editor() as editor:
                try:
                    await editor.load_project(task.initial_project, spec.project_limits)
                except ProjectFormatError as exc:
                    message = f"the task's initial project cannot be loaded: {exc}"
                    return _finish(EpisodeResult.errored(spec, "task_invalid", message), started, clock, timings)
                environment = await self._environment(spec, editor)
                if isinstance(agent, NeedsEditor):
                    await _begin(agent, editor)
                if isinstance(agent, ConversingAgent):
                    await agent.brief(await environment.block_catalog())
                timings.setup_s = time.perf_counter() - clock
                stop_reason = await _act(agent, editor, environment, spec, steps)
                timings.agent_s = time.perf_counter() - clock - timings.setup_s
                final_project = await editor.save_project()
        except (EditorError, BridgeError) as exc:
            result = EpisodeResult.errored(spec, "editor_failure", f"{type(exc).__name__}: {exc}", steps=steps)
            return _finish(result, started, clock, timings)
        except AgentCrashedError as exc:
            result = EpisodeResult.errored(spec, "agent_error", str(exc), steps=steps)
            return _finish(result, started, clock, timings)
        except ModelCallError as exc:  # the model cannot be reached or refuses: no verdict about it
            result = EpisodeResult.errored(spec, exc.error_class, str(exc), steps=steps)
            return _finish(_with_images(result, agent), started, clock, timings)
        evaluation_start = time.perf_counter()
        evaluation = await self.evaluator.evaluate(final_project, task.evaluation, spec.project_limits)
        timings.evaluation_s = time.perf_counter() - evaluation_start
        outcome, error_class = outcome_of(evaluation)
        result = EpisodeResult(
            job_id=spec.job_id,
            attempt=spec.attempt,
            outcome=outcome,
            error_class=error_class,
            error_message=evaluation.error.message if error_class and evaluation.error else None,
            stop_reason=stop_reason,
            evaluation=evaluation,
            steps=steps,
            final_project=final_project,
        )
        return _finish(_with_images(result, agent), started, clock, timings)


async def _begin(agent: NeedsEditor, editor: Editor) -> None:
    try:
        await agent.begin(editor)
    except (EditorError, BridgeError):
        raise
    except Exception as exc:
        raise AgentCrashedError(f"the agent failed to start: {type(exc).__name__}: {exc}") from exc


async def _act(
    agent: Agent, editor: Editor, environment: Environment, spec: EpisodeSpec, steps: list[StepRecord]
) -> str:
    """The agent loop; returns why it stopped."""
    for index in range(spec.max_steps):
        step_start = time.perf_counter()
        observation = await environment.observe() if agent.observes else None
        observation_s = time.perf_counter() - step_start
        try:
            action = await agent.act(observation)
        except (EditorError, BridgeError, ModelCallError):
            raise
        except Exception as exc:  # a broken agent is the agent's error, not the harness's
            raise AgentCrashedError(f"the agent raised {type(exc).__name__} at step {index}: {exc}") from exc
        ok, error_code, error_message, data = await _apply(editor, environment, action, spec.project_limits)
        name, args = _describe(action)
        step = StepRecord(
            index=index,
            action=name,
            args=args,
            ok=ok,
            error_code=error_code,
            error_message=error_message,
            data=data,
            latency_s=time.perf_counter() - step_start,
            observation_s=observation_s,
            warnings=list(getattr(observation, "warnings", [])),
        )
        steps.append(agent.after_step(step) if isinstance(agent, ConversingAgent) else step)
        if action.name in FINAL_ACTIONS:
            return action.name
    return "max_steps"


async def _apply(
    editor: Editor, environment: Environment, action: Action, limits: ProjectLimits
) -> tuple[bool, str | None, str | None, JsonValue]:
    """Carry out one action: (ok, error code, error message, data the environment answered)."""
    if isinstance(action, InvalidReply):
        return False, "INVALID_REPLY", action.message, {"reason": action.reason}
    if isinstance(action, LoadProject):
        try:
            await editor.load_project(action.sb3, limits)
        except ProjectTooLargeError as exc:
            return False, "project_too_large", str(exc), None
        except ProjectFormatError as exc:
            return False, "project_invalid", str(exc), None
        except BridgeError as exc:
            return False, exc.kind, exc.detail, None
    if isinstance(action, CompositeAction | PrimitiveAction):
        envelope = await environment.execute(action)
        if envelope.error is not None:
            return False, envelope.error.code, envelope.error.message, envelope.error.details
        return True, None, None, envelope.data
    return True, None, None, None


def _describe(action: Action) -> tuple[str, dict[str, JsonValue]]:
    """The action's name and arguments as they are logged (bulky payloads by size only)."""
    if isinstance(action, LoadProject):
        return action.name, {"sb3_bytes": len(action.sb3)}
    if isinstance(action, CompositeAction | PrimitiveAction):
        size = len(json.dumps(action.args, ensure_ascii=False))
        return action.api, action.args if size <= MAX_LOGGED_ARGS else {"args_chars": size}
    return action.name, action.model_dump(exclude={"name"})


def _with_images(result: EpisodeResult, agent: Agent) -> EpisodeResult:
    if isinstance(agent, ConversingAgent) and agent.images:
        return result.model_copy(update={"images": dict(agent.images)})
    return result


def _finish(result: EpisodeResult, started: float, clock: float, timings: EpisodeTimings) -> EpisodeResult:
    timings.total_s = time.perf_counter() - clock
    return result.model_copy(update={"timings": timings, "started_at": started, "finished_at": time.time()})
