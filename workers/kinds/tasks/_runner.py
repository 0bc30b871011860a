"""One episode: open the editor on the initial project, let the agent act, evaluate what it left.

The agent works in its own page; the evaluation runs in another, clean page, so nothing the agent
left running in its VM can influence the verdict. Both pages are fresh, or, with an ``EditorPool``,
recycled after an earlier episode or evaluation and verified as good as fresh.

On the virtual episode clock (``EpisodeSpec.episode_clock``) the agent's page time stands still
while the agent decides and moves by a fixed amount after each action.

While other episodes of the worker act, a virtual-clock evaluation gives way to them (see
``WorkerBrowser.evaluate_giving_way``).
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import time
import traceback
from collections.abc import Awaitable, Callable
from typing import TypeVar

from pydantic import JsonValue

from workers.actor._browser import WorkerBrowser
from workers.agent_api import Agent, AgentMemory, EpisodeEnd, Privileges, StepResult, TaskContext
from workers.agents import EpisodeModels
from workers.contract import (
    FINAL_ACTIONS,
    Action,
    AgentUnableError,
    BridgeError,
    CompositeAction,
    Done,
    EditorError,
    EpisodeTimings,
    EpisodeVideo,
    ErrorClass,
    Failed,
    InvalidReply,
    JobResult,
    LLMSettings,
    LoadProject,
    ModelCallError,
    Observation,
    ObservationSettings,
    ParticipantLeftError,
    PrimitiveAction,
    ProjectFormatError,
    ProjectLimits,
    ProjectTooLargeError,
    RecordSettings,
    StepObservation,
    StepRecord,
    TaskPayload,
    evaluation_seed,
    outcome_of,
    with_random_seed,
)
from workers.editor import Editor
from workers.kinds.tasks._contract import EpisodeSpec
from workers.kinds.tasks._environment import CompositeEnvironment, Environment, PrimitiveEnvironment
from workers.kinds.tasks._pace import Pace
from workers.kinds.tasks._start_garbage import StartGarbage
from workers.kinds.tasks._turns import Turn, Turns
from workers.llm import ModelCache
from workers.ocr import RegionOCR
from workers.primitive import PrimitiveObserver, region_ocr
from workers.tracing import set_attributes, span
from workers.video import EpisodeRecorder

MAX_LOGGED_ARGS = 16_384
"""Arguments longer than this (as JSON characters) are logged by size: no action accepts that much
(the longest value any takes is 10,000 characters), and a runaway payload would fill every row and file."""

_T = TypeVar("_T")

ACTION_TYPES = (Done, Failed, LoadProject, InvalidReply, CompositeAction, PrimitiveAction)
"""What ``act`` may return (the members of ``Action``)."""

PRIMITIVE_STAGE = "small"
"""Primitive episodes show the small stage, like the upstream harness (more room for blocks)."""


class AgentCrashedError(Exception):
    """The agent raised instead of doing its part; ``trace`` is its traceback for the trajectory, ``error_class``
    says whether a retry can help (``agent_unable``: the agent said it cannot; ``agent_error``: a crash)."""

    def __init__(self, message: str, trace: str, error_class: ErrorClass = "agent_error") -> None:
        super().__init__(message)
        self.trace = trace
        self.error_class = error_class


STARTS_AT_ONCE = 1
"""Episodes of one runner (one browser) that start at once: take an editor, load the project, and make the first
observation (or the first model call, whichever comes first).

Starting is CPU-bound (loading, settling, ``start_ms`` of frames on the virtual clock, a primitive first
observation's OCR), so starting many at once only makes each later; one after the other, the first agent acts
sooner and steps do not all fall at the same moments (32 episodes on 2 cores: every step waited seconds). With
the turn given back before the first observation, 16 primitive episodes on 2 cores saw theirs 8.6 s into their
first step at the median, all at the ramp's end, and then stepped in cohorts (11 drags in one second)."""


class EpisodeRunner:
    """Runs episodes in one browser session; safe to use for several episodes at once."""

    def __init__(self, browser: WorkerBrowser) -> None:
        """Episodes open their editors in ``browser`` (from its pool, if it has one) and are judged by its evaluator."""
        self.browser = browser
        self._starts = Turns(STARTS_AT_ONCE)
        self._ocr: dict[ObservationSettings, RegionOCR | None] = {}
        """One OCR engine (and region cache) per setting, shared by this runner's episodes."""

    @property
    def waiting_to_start(self) -> int:
        """Episodes queued for their start turn (``STARTS_AT_ONCE``), holding no editor yet."""
        return self._starts.waiting

    async def _environment(self, spec: EpisodeSpec, editor: Editor, pace: Pace) -> Environment:
        if spec.mode == "composite":
            return CompositeEnvironment(editor)
        await editor.set_stage_size(PRIMITIVE_STAGE)
        settings = spec.observation or ObservationSettings()
        if settings not in self._ocr:
            self._ocr[settings] = region_ocr(settings)
        pass_time = pace.pass_time if pace.virtual else None
        return PrimitiveEnvironment(editor, PrimitiveObserver(settings, self._ocr[settings]), pass_time)

    async def run(self, spec: EpisodeSpec, task: TaskPayload, agent: Agent) -> JobResult:
        started, clock = time.time(), time.perf_counter()
        timings = EpisodeTimings()
        steps: list[StepRecord] = []
        cache = ModelCache(spec.model_cache.dir) if spec.model_cache is not None else None
        models = EpisodeModels((spec.llm or LLMSettings()).retry, spec.seed, cache=cache)
        memory = AgentMemory(spec.memory, spec.job_id, task.task_id)
        recording = _Recording()
        try:
            async with (
                Turn(self._starts) as starting,
                self.browser.pool.editor()
                if self.browser.pool is not None
                else self.browser.session.editor() as editor,
                recording,  # stopped before the editor goes back, however the episode ends
            ):
                editor.uses += 1
                try:
                    await editor.load_project(task.initial_project, spec.project_limits)
                except ProjectFormatError as exc:
                    message = f"the task's initial project cannot be loaded: {exc}"
                    return await _finish(
                        JobResult.errored(spec, "task_invalid", message), started, clock, timings, recording
                    )
                await editor.seed_random(evaluation_seed(spec.task_id, spec.seed))
                pace = Pace(
                    editor, spec.episode_clock, stage_seen=sees_stage(spec.mode, agent), filmed=spec.record.video
                )
                environment = await self._environment(spec, editor, pace)
                await recording.start(editor, spec.record)
                await pace.start()
                garbage = StartGarbage(editor)

                def before_model_call() -> None:
                    starting.release()  # a model call in the agent's start waits for no one
                    garbage.collect()  # the page waits now: it does so with ~35 MB less

                models.before_call = before_model_call
                context = _context(spec, task, agent, editor, environment, models, memory)
                stop_reason = "internal_error"
                self.browser.acting += 1
                try:
                    await _guarded(agent.start(context), "failed to start")
                    timings.setup_s = time.perf_counter() - clock
                    stop_reason = await _act(agent, environment, spec, steps, models, pace, starting.release)
                except ModelCallError as exc:
                    stop_reason = exc.error_class
                    raise
                except AgentCrashedError as exc:
                    stop_reason = exc.error_class
                    raise
                except (EditorError, BridgeError):
                    stop_reason = "editor_failure"
                    raise
                finally:
                    garbage.end()
                    await recording.stop()  # the video ends with the agent's last step
                    self.browser.acting -= 1
                    ended = agent.finish(EpisodeEnd(stop_reason=stop_reason, steps=len(steps)))
                    if stop_reason in (*FINAL_ACTIONS, "max_steps"):
                        await _guarded(ended, "failed to finish")
                    else:  # the episode is an error already: the agent's own failure to finish adds nothing
                        with contextlib.suppress(Exception):
                            await ended
                    _book_late_calls(steps, models, stop_reason)
                timings.agent_s = time.perf_counter() - clock - timings.setup_s
                final_project = await editor.save_project()
        except (EditorError, BridgeError) as exc:
            result = JobResult.errored(spec, "editor_failure", f"{type(exc).__name__}: {exc}", steps=steps)
            return await _finish(result, started, clock, timings, recording)
        except AgentCrashedError as exc:
            steps.append(_crash_step(len(steps), exc))
            result = JobResult.errored(spec, exc.error_class, str(exc), steps=steps)
            return await _finish(_with_agent_outputs(result, models, memory), started, clock, timings, recording)
        except ModelCallError as exc:  # the model cannot be reached or refuses: no verdict about it
            result = JobResult.errored(spec, exc.error_class, str(exc), steps=steps)
            return await _finish(_with_agent_outputs(result, models, memory), started, clock, timings, recording)
        evaluation_start = time.perf_counter()
        judging = with_random_seed(task.evaluation, evaluation_seed(spec.task_id, spec.seed))
        with span("evaluation", task=spec.task_id) as evaluating:
            evaluation = await self.browser.evaluate_giving_way(final_project, judging, spec.project_limits)
            outcome, error_class = outcome_of(evaluation)
            set_attributes(
                evaluating, outcome=outcome, error_class=error_class, tests_passed=evaluation.passed,
                tests_total=evaluation.total,
            )  # fmt: skip
        timings.evaluation_s = time.perf_counter() - evaluation_start
        result = JobResult(
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
        return await _finish(_with_agent_outputs(result, models, memory), started, clock, timings, recording)


def sees_stage(mode: str, agent: Agent) -> bool:
    """Whether the agent may look at the stage's picture: primitive screenshots, or an agent with the live page."""
    return mode == "primitive" or getattr(agent, "privileged", False) or getattr(agent, "acts_live", False)


def _context(
    spec: EpisodeSpec,
    task: TaskPayload,
    agent: Agent,
    editor: Editor,
    environment: Environment,
    models: EpisodeModels,
    memory: AgentMemory,
) -> TaskContext:
    privileges = None
    if getattr(agent, "acts_live", False):  # a person's relay: the live editor, never the solution
        privileges = Privileges(
            initial_project=task.initial_project, golden_project=None, golden_trajectory=None, editor=editor
        )
    elif getattr(agent, "privileged", False):
        privileges = Privileges(
            initial_project=task.initial_project,
            golden_project=task.golden_project,
            golden_trajectory=task.golden_trajectory,
            editor=editor,
        )
    return TaskContext(
        task_id=task.task_id,
        category=task.category,
        instruction=task.instruction,
        mode=spec.mode,
        max_steps=spec.max_steps,
        seed=spec.seed,
        block_catalog=environment.block_catalog,
        model=spec.model,
        connect=models.connect,
        llm=spec.llm,
        privileges=privileges,
        memory=memory,
    )


async def _guarded(call: Awaitable[_T], doing: str) -> _T:
    """Await one of the agent's calls: the editor's and the model's failures pass, the agent's own are its error."""
    try:
        return await call
    except (EditorError, BridgeError, ModelCallError, AgentCrashedError):
        raise
    except ParticipantLeftError as exc:  # a person's page closed: their job is retried, not judged
        raise AgentCrashedError(str(exc), str(exc), "participant_left") from exc
    except Exception as exc:  # a broken agent is the agent's error, not the harness's
        unable = isinstance(exc, AgentUnableError)
        message = f"the agent {doing}: {type(exc).__name__}: {exc}"
        raise AgentCrashedError(message, _trace(exc), "agent_unable" if unable else "agent_error") from exc


async def _act(
    agent: Agent,
    environment: Environment,
    spec: EpisodeSpec,
    steps: list[StepRecord],
    models: EpisodeModels,
    pace: Pace,
    observed: Callable[[], None],
) -> str:
    """The agent loop; returns why it stopped. ``observed`` is called after each observation."""
    last: StepResult | None = None
    for index in range(spec.max_steps):
        with span("step", index=index, task=spec.task_id, mode=spec.mode) as stepping:
            step, last, name = await _step(agent, environment, spec, models, pace, index, last, observed)
            set_attributes(
                stepping, action=step.action, ok=step.ok, error_code=step.error_code, llm_calls=step.llm_calls,
                input_tokens=step.input_tokens, output_tokens=step.output_tokens,
            )  # fmt: skip
        steps.append(step)
        if name in FINAL_ACTIONS:
            return name
    return "max_steps"


async def _step(
    agent: Agent,
    environment: Environment,
    spec: EpisodeSpec,
    models: EpisodeModels,
    pace: Pace,
    index: int,
    last: StepResult | None,
    observed: Callable[[], None],
) -> tuple[StepRecord, StepResult, str]:
    """One step: observe, let the agent choose, carry out its action. The step as recorded, what the agent is told
    of it, and the action's name (a final one ends the episode)."""
    step_start, started_at = time.perf_counter(), time.time()
    episode_clock_ms = pace.elapsed_ms if pace.virtual else None
    observation = await environment.observe() if getattr(agent, "observes", True) else None
    observation_s = time.perf_counter() - step_start
    observed()
    action = await _guarded(agent.act(observation, last), f"raised at step {index}")
    if not isinstance(action, ACTION_TYPES):
        message = f"the agent returned a {type(action).__name__} at step {index}, not an action"
        raise AgentCrashedError(message, message)
    with span("action", action=getattr(action, "api", None) or action.name) as acting:
        await pace.before_action()
        ok, error_code, error_message, data = await _apply(
            environment,
            action,
            spec.project_limits,
            privileged=getattr(agent, "privileged", False),
            live=getattr(agent, "acts_live", False),
        )
        await pace.after_action()
        set_attributes(acting, ok=ok, error_code=error_code)
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
        observation=_recorded(observation, models),
        started_at=started_at,
        episode_clock_ms=episode_clock_ms,
    )
    told = StepResult(ok=ok, error_code=error_code, error_message=error_message, data=data)
    return models.drain().booked_on(step), told, action.name


def _recorded(observation: Observation | None, models: EpisodeModels) -> StepObservation | None:
    """What the step was shown, for the trajectory; a screenshot joins the episode's images (once per digest)."""
    if observation is None:
        return None
    record, screenshot = StepObservation.of(observation)
    if screenshot is not None and record.screenshot is not None:
        models.images.setdefault(record.screenshot, screenshot)
    return record


async def _apply(
    environment: Environment, action: Action, limits: ProjectLimits, *, privileged: bool, live: bool = False
) -> tuple[bool, str | None, str | None, JsonValue]:
    """Carry out one action: (ok, error code, error message, data the environment answered). ``live``: the agent's
    gestures have happened in the editor already (a person's, relayed as they made them): recorded, not repeated."""
    if live and isinstance(action, CompositeAction | PrimitiveAction):
        return True, None, None, {"live": True}
    if isinstance(action, InvalidReply):
        return False, "INVALID_REPLY", action.message, {"reason": action.reason}
    if isinstance(action, LoadProject) and not privileged:
        return False, "PRIVILEGED_ACTION", "only privileged agents (oracles) may replace the whole project", None
    if isinstance(action, LoadProject):
        try:
            await environment.editor.load_project(action.sb3, limits)
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


def _with_agent_outputs(result: JobResult, models: EpisodeModels, memory: AgentMemory) -> JobResult:
    """The result with the images the prompts showed and what the agent proposed to learn from."""
    return result.model_copy(update={"images": dict(models.images), "memory_items": list(memory.items)})


TRACE_LIMIT = 8_000
"""Characters of an agent's traceback kept in its trajectory."""


def _trace(exc: BaseException) -> str:
    text = "".join(traceback.format_exception(exc))
    return text if len(text) <= TRACE_LIMIT else "...\n" + text[-TRACE_LIMIT:]


def _book_late_calls(steps: list[StepRecord], models: EpisodeModels, stop_reason: str) -> None:
    """Model calls made after the last action (in ``finish``, e.g. a self-evaluation), or before a first
    action that never came, are booked too: no call goes uncounted."""
    calls = models.drain()
    if not calls.llm_calls:
        return
    if not steps:  # the agent broke (or its model failed) before its first action
        message = "model calls made before the episode ended without an action"
        steps.append(StepRecord(index=0, action="start", ok=False, error_code=stop_reason, error_message=message))
    steps[-1] = calls.booked_on(steps[-1])


def _crash_step(index: int, exc: AgentCrashedError) -> StepRecord:
    """The trajectory's last entry when the agent raised: what it raised, with its traceback."""
    kind = exc.error_class
    return StepRecord(index=index, action=kind, ok=False, error_code=kind, error_message=exc.trace)


class _Recording:
    """An episode's video, when its spec asks for one: the agent's page from just before its first page time
    (``Pace.start``) to the end of its last step, or to where the episode broke off."""

    def __init__(self) -> None:
        self._recorder: EpisodeRecorder | None = None
        self._encoding: asyncio.Future[EpisodeVideo | None] | None = None

    async def start(self, editor: Editor, settings: RecordSettings) -> None:
        if settings.video:
            self._recorder = EpisodeRecorder(editor.page, settings)
            await self._recorder.start()

    async def stop(self) -> None:
        """Idempotent; called as the agent's part ends, however it ends. The encoder finishes the video while
        the episode goes on to its evaluation: nothing waits for it before the episode's result."""
        recorder, self._recorder = self._recorder, None
        if recorder is not None:
            self._encoding = await recorder.stop()

    async def video(self) -> EpisodeVideo | None:
        return None if self._encoding is None else await self._encoding

    async def __aenter__(self) -> _Recording:
        return self

    async def __aexit__(self, *exc: object) -> None:
        await self.stop()


async def _finish(
    result: JobResult, started: float, clock: float, timings: EpisodeTimings, recording: _Recording
) -> JobResult:
    video = await recording.video()
    timings.total_s = time.perf_counter() - clock
    return result.model_copy(
        update={"timings": timings, "started_at": started, "finished_at": time.time(), "video": video}
    )
