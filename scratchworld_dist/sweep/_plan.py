"""Planning: the job matrix model x mode x task x seed, each job named by what decides its outcome.

A job id is a hash of everything that can change the job's result (model and its parameters,
mode, agent, the task's content, seed, step limit, project limits, and the harness fingerprint:
the digest of the code and editor that run it), so a changed task, config or harness is a new
job and a stale result is never reused; identical jobs keep their id across runs, which is what
resume relies on.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Iterable, Iterator, Mapping
from pathlib import Path
from typing import Literal, Protocol

from pydantic import BaseModel, ConfigDict

from scratchworld_dist._errors import ProjectFormatError, SuiteError
from scratchworld_dist._files import FileTooLargeError, read_file
from scratchworld_dist.kinds import DEFAULT_KIND, job_kind
from scratchworld_dist.memory import store_name, task_waves
from scratchworld_dist.suites import Task
from scratchworld_dist.suites._task import read_trajectory
from workers.contract import (
    MIB,
    AgentRef,
    AnswerFormat,
    ConnectionKind,
    DragSetting,
    DragType,
    EpisodeClock,
    EvaluationClock,
    EvaluationProfile,
    EvaluationRender,
    EvaluationTiming,
    LLMSettings,
    MemoryPlacement,
    MemorySettings,
    MemorySnapshot,
    Mode,
    ModelCacheSettings,
    ModelSpec,
    ObservationSettings,
    PerceptionKind,
    ProjectLimits,
    SyntheticEpisodes,
    TaskPayload,
    ValueKind,
    WorkerJob,
    check_project,
)
from workers.kinds import kind_fingerprint
from workers.node import harness_fingerprint

NO_MODEL = "-"
"""Model label of scripted agents (oracle, noop) that call no model."""


class DragTaskInfo(BaseModel):
    """What reports group a drag job by (its task's type, connection kind and source)."""

    model_config = ConfigDict(frozen=True)

    type: DragType
    connection: ConnectionKind
    source: Literal["canvas", "flyout"]


class PerceptionItemInfo(BaseModel):
    """What reports group a perception job by (its item's kind, tag and form of answer), and its question."""

    model_config = ConfigDict(frozen=True)

    question: str
    kind: PerceptionKind
    tag: str
    answer_format: AnswerFormat
    value_kind: ValueKind | None = None


class JobSpec(BaseModel):
    """One cell of the matrix, as planned by the driver: a job of the kind ``benchmark`` names."""

    model_config = ConfigDict(frozen=True)

    job_id: str
    benchmark: str = DEFAULT_KIND
    """The job's kind (``scratchworld_dist.kinds``): what builds its worker job and its own rows."""

    model: ModelSpec | None
    mode: Mode
    agent: AgentRef
    agent_code: str | None = None
    """Digest of a plugin agent's code (None for the built-in agents, which the harness fingerprint covers)."""

    task_id: str
    category: str
    task_hash: str
    seed: int
    max_steps: int
    observation: ObservationSettings | None = None
    """How primitive observations are made (None in composite mode)."""

    llm: LLMSettings | None = None
    """The conversation protocol of model-driven agents (None for jobs without a model)."""

    project_limits: ProjectLimits = ProjectLimits()
    harness: str
    """The harness fingerprint the job was planned under (part of its id)."""

    extra_models: list[ModelSpec] = []
    """Models the agent calls besides ``model`` (e.g. a grounding model), as its params name them."""

    memory: MemoryPlacement | None = None
    """The job's memory stream and wave (learning agents; part of its id)."""

    episode_clock: EpisodeClock = EpisodeClock()
    """How time passes on the agent's page (part of the id when virtual)."""

    memory_snapshot: MemorySnapshot | None = None
    """The memory the job is shown: set by the driver when the job's wave starts (not part of its id)."""

    model_cache: ModelCacheSettings | None = None
    """The sweep's model cache (not part of the id: a replayed reply is the one this model gave to this
    exact request under this seed, so the job's conditions are the same; rows record the hits)."""

    setting: DragSetting | None = None
    """A drag job's setting (part of its id); None for episodes."""

    drag: DragTaskInfo | None = None
    """A drag job's task, as reports group it."""

    element_list: bool = False
    """A drag job shows the element list (part of its id)."""

    perception: PerceptionItemInfo | None = None
    """A perception job's item, as reports group it."""

    @property
    def needs_browser(self) -> bool:
        """Whether the job's worker opens an editor (a perception job reads a static screenshot)."""
        return job_kind(self.benchmark).needs_browser

    @property
    def agent_label(self) -> str:
        """The agent column of reports; memory fed by the verdict is labelled as the ablation it is."""
        if self.memory is not None and self.memory.settings.learn_from == "verdict_ablation":
            return f"{self.agent.display} [verdict-fed ablation]"
        return self.agent.display

    @property
    def model_name(self) -> str:
        """The model column of reports: the job's model, joined by any others its agent calls."""
        if self.model is None:
            return NO_MODEL
        return "+".join([self.model.name, *(extra.name for extra in self.extra_models)])

    def episode(self, attempt: int, timeout_s: float) -> WorkerJob:
        """What the worker is sent for ``attempt``, as the job's kind builds it."""
        return job_kind(self.benchmark).worker_job(self, attempt, timeout_s)


class TaskContent(BaseModel):
    """A task read into memory: its payload for workers and the hash of all of it."""

    model_config = ConfigDict(frozen=True)

    task: Task
    payload: TaskPayload
    task_hash: str


def read_project(path: Path, limits: ProjectLimits) -> bytes:
    """A task's project, read only if its size is within the limits and checked to be a project."""
    try:
        data = read_file(path, int(limits.max_file_mb * MIB))
    except FileTooLargeError as exc:
        raise SuiteError(f"the project is {exc.strerror}, over project_limits.max_file_mb", path) from exc
    except OSError as exc:
        raise SuiteError(f"cannot read the project: {exc.strerror or exc}", path) from exc
    try:
        check_project(data, limits)
    except ProjectFormatError as exc:
        raise SuiteError(str(exc), path) from exc
    return data


def read_task(
    task: Task,
    profile: EvaluationProfile | None = None,
    clock: EvaluationClock | None = None,
    limits: ProjectLimits | None = None,
    render: EvaluationRender | None = None,
    trajectories: Path | None = None,
    timing: EvaluationTiming | None = None,
) -> TaskContent:
    """Read a task's files once; the hash covers every byte a worker will see (and profile and clock).

    Its projects are checked against ``limits`` here, so a task no worker would load fails the plan.
    A task that ships no golden trajectory takes ``trajectories/<task id>.json`` (``scratchworld
    oracle-plan``'s output) when a folder is given.
    """
    limits = limits or ProjectLimits()
    spec = task.evaluation_spec(profile, clock, render, timing)
    golden = read_project(task.golden_project, limits) if task.golden_project is not None else None
    trajectory = task.trajectory()
    if trajectory is None and trajectories is not None:
        planned = trajectories / f"{task.id}.json"
        if not planned.is_file():
            raise SuiteError(f"no planned trajectory for task {task.id} (run scratchworld oracle-plan)", planned)
        trajectory = read_trajectory(planned)
    payload = TaskPayload(
        task_id=task.id,
        category=task.category,
        instruction=task.instruction,
        initial_project=read_project(task.initial_project, limits),
        golden_project=golden,
        golden_trajectory=trajectory,
        evaluation=spec,
    )
    digest = hashlib.sha256()
    for part in (
        task.id.encode(),
        task.category.encode(),
        task.instruction.encode(),
        payload.initial_project,
        golden or b"",
        b"" if trajectory is None else json.dumps([a.model_dump(mode="json") for a in trajectory]).encode(),
        spec.model_dump_json().encode(),
    ):
        digest.update(len(part).to_bytes(8, "big"))
        digest.update(part)
    return TaskContent(task=task, payload=payload, task_hash=digest.hexdigest()[:16])


class HashedContent(Protocol):
    """A task read into memory (a ``TaskContent`` or a drag task's ``DragContent``)."""

    @property
    def task_hash(self) -> str: ...


def suite_hash(contents: Iterable[HashedContent]) -> str:
    """One hash for the selected tasks' contents (order-independent)."""
    digest = hashlib.sha256()
    for task_hash in sorted(content.task_hash for content in contents):
        digest.update(task_hash.encode())
    return digest.hexdigest()[:16]


def agent_identity(agent: AgentRef, code: str | None) -> dict[str, object]:
    """An agent as a single-step job's id names it: its name and params, and a plugin's code digest (None for
    the harness's own agents, whose ids stay as they were: the harness fingerprint covers their code)."""
    return agent.identity() if code is None else {**agent.identity(), "code": code}


def identity_id(identity: Mapping[str, object]) -> str:
    """A job's name: the SHA-256 of its identity as canonical JSON, 24 hex digits (every job kind names its jobs so)."""
    canonical = json.dumps(identity, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(canonical.encode()).hexdigest()[:24]


def job_id(
    model: ModelSpec | None,
    mode: str,
    agent: AgentRef | str,
    task_hash: str,
    task_id: str,
    seed: int,
    max_steps: int,
    observation: ObservationSettings | None = None,
    llm: LLMSettings | None = None,
    project_limits: ProjectLimits | None = None,
    harness: str | None = None,
    synthetic: SyntheticEpisodes | None = None,
    agent_code: str | None = None,
    memory: MemoryPlacement | None = None,
    episode_clock: EpisodeClock | None = None,
) -> str:
    """The job's name: a hash of everything that can change its result (``harness``: this code's fingerprint;
    ``synthetic``: the behaviour of a browserless stand-in episode, never to be taken for a real one;
    ``agent_code``: a plugin agent's code digest; ``memory``: a learning agent's stream and wave;
    ``episode_clock``: how time passes on the agent's page)."""
    ref = AgentRef.model_validate(agent)
    identity: dict[str, object] = {
        "model": None if model is None else model.identity(),
        "mode": mode,
        # A built-in agent without parameters is named by its name alone (ids stay as they were).
        "agent": ref.name if not ref.params and agent_code is None else {**ref.identity(), "code": agent_code},
        "task": [task_id, task_hash],
        "seed": seed,
        "max_steps": max_steps,
        "project_limits": (project_limits or ProjectLimits()).model_dump(mode="json"),
        "harness": harness or kind_fingerprint(harness_fingerprint(), "tasks").digest,
    }
    if observation is not None:  # only primitive jobs have one, so composite ids stay as they were
        identity["observation"] = observation.model_dump(mode="json")
    if llm is not None:  # only jobs with a model have one
        identity["llm"] = llm.identity()
    if synthetic is not None:  # only synthetic jobs
        identity["synthetic"] = synthetic.model_dump(mode="json")
    if memory is not None:  # only jobs of learning agents
        identity["memory"] = memory.identity()
    if episode_clock is not None and episode_clock.mode != "real":  # ids of real-clock jobs stay as they were
        identity["episode_clock"] = episode_clock.model_dump(mode="json")
    return identity_id(identity)


def plan_jobs(
    models: list[ModelSpec | None],
    modes: list[Mode],
    agent: AgentRef,
    tasks: list[TaskContent],
    seeds: list[int],
    max_steps: int | Mapping[Mode, int],
    observation: ObservationSettings | None = None,
    llm: LLMSettings | None = None,
    project_limits: ProjectLimits | None = None,
    harness: str | None = None,
    synthetic: SyntheticEpisodes | None = None,
    agent_code: str | None = None,
    extra_models: list[ModelSpec] | None = None,
    memory: MemorySettings | None = None,
    memory_sources: Mapping[tuple[str, Mode], str] | None = None,
    episode_clock: EpisodeClock | None = None,
    model_cache: ModelCacheSettings | None = None,
) -> Iterator[JobSpec]:
    """The matrix in a stable order: model, mode, seed, then suite order of tasks.

    With ``memory``, each (model, mode, seed) is a stream whose tasks fall into waves;
    ``memory_sources`` gives offline memory's source digest per (model name, mode); ``model_cache``
    is handed to every job (it does not change their ids)."""
    limits = project_limits or ProjectLimits()
    clock = episode_clock or EpisodeClock()
    harness = harness or kind_fingerprint(harness_fingerprint(), "tasks").digest
    waves = task_waves([content.task.id for content in tasks], memory) if memory is not None else {}
    for model in models:
        for mode in modes:
            steps = max_steps if isinstance(max_steps, int) else max_steps[mode]
            settings = (observation or ObservationSettings()) if mode == "primitive" else None
            protocol = (llm or LLMSettings()) if model is not None else None
            for seed in seeds:
                for content in tasks:
                    task = content.task
                    stand_in = synthetic if synthetic is not None and synthetic.covers(task.id) else None
                    placement = None
                    if memory is not None:
                        label = model.name if model is not None else NO_MODEL
                        source = (memory_sources or {}).get((label, mode))
                        store = store_name(label, mode, seed)
                        placement = MemoryPlacement(store=store, wave=waves[task.id], settings=memory, source=source)
                    name = job_id(
                        *(model, mode, agent, content.task_hash, task.id, seed, steps, settings, protocol),
                        *(limits, harness, stand_in, agent_code, placement, clock),
                    )
                    yield JobSpec(
                        job_id=name,
                        model=model,
                        mode=mode,
                        agent=agent,
                        agent_code=agent_code,
                        task_id=task.id,
                        category=task.category,
                        task_hash=content.task_hash,
                        seed=seed,
                        max_steps=steps,
                        observation=settings,
                        llm=protocol,
                        project_limits=limits,
                        harness=harness,
                        extra_models=list(extra_models or []),
                        memory=placement,
                        episode_clock=clock,
                        model_cache=model_cache,
                    )
