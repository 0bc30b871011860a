"""Planning task episodes: the job matrix model x mode x task x seed, each job named by what decides its outcome
(model and its parameters, mode, agent, the task's content, seed, step limit, project limits, observation
and conversation settings, memory placement, the page clock and the harness fingerprint)."""

from __future__ import annotations

import hashlib
import json
from collections.abc import Iterator
from pathlib import Path
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict

from scratchworld_dist._errors import SuiteError
from scratchworld_dist.memory import store_name, task_waves
from scratchworld_dist.suites import Task, read_trajectory
from scratchworld_dist.sweep import NO_MODEL, JobBody, JobSpec, identity_id, read_project
from workers.contract import (
    AgentRef,
    ClockMode,
    EpisodeClock,
    EvaluationClock,
    EvaluationPage,
    EvaluationProfile,
    EvaluationRender,
    EvaluationTiming,
    LLMSettings,
    MemoryPlacement,
    MemorySettings,
    Mode,
    ModelCacheSettings,
    ModelSpec,
    ObservationSettings,
    ProjectLimits,
    RecordSettings,
    SyntheticEpisodes,
    TaskPayload,
)
from workers.kinds import kind_fingerprint
from workers.node import harness_fingerprint

PRIMITIVE_STEP_LENGTH = 2
"""A primitive step against a composite one, for ordering a sweep's jobs: it observes a screenshot, the element
list and OCR, and acts by real gestures (the oracle's step: 0.18 s against 0.02 s on 2 cores), and its model
reads an image; a model's own time, the same in both modes, narrows the gap."""


class EpisodeBody(JobBody):
    """An episode's own settings: its mode and step limit, how it observes, what it may load, its page clock."""

    kind: Literal["tasks"] = "tasks"
    mode: Mode
    max_steps: int
    observation: ObservationSettings | None = None
    """How primitive observations are made (None in composite mode)."""

    project_limits: ProjectLimits = ProjectLimits()
    episode_clock: EpisodeClock = EpisodeClock()
    """How time passes on the agent's page (part of the id when virtual)."""

    record: RecordSettings = RecordSettings()
    """What is recorded besides the steps (a video): not part of the id."""

    def columns(self) -> dict[str, Any]:
        return {"mode": self.mode, "max_steps": self.max_steps}

    @property
    def page_clock(self) -> ClockMode:
        return self.episode_clock.mode

    @property
    def expected_length(self) -> float:
        """Its step limit, a primitive step counted as ``PRIMITIVE_STEP_LENGTH`` composite ones."""
        return self.max_steps * (PRIMITIVE_STEP_LENGTH if self.mode == "primitive" else 1)


class TaskContent(BaseModel):
    """A task read into memory: its payload for workers and the hash of all of it."""

    model_config = ConfigDict(frozen=True)

    task: Task
    payload: TaskPayload
    task_hash: str


def read_task(
    task: Task,
    profile: EvaluationProfile | None = None,
    clock: EvaluationClock | None = None,
    limits: ProjectLimits | None = None,
    render: EvaluationRender | None = None,
    trajectories: Path | None = None,
    timing: EvaluationTiming | None = None,
    page: EvaluationPage | None = None,
) -> TaskContent:
    """Read a task's files once; the hash covers every byte a worker will see (and profile and clock).

    Its projects are checked against ``limits`` here, so a task no worker would load fails the plan.
    A task that ships no golden trajectory takes ``trajectories/<task id>.json`` (``scratchworld
    oracle-plan``'s output) when a folder is given.
    """
    limits = limits or ProjectLimits()
    spec = task.evaluation_spec(profile, clock, render, timing, page=page)
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
        identity["synthetic"] = synthetic.model_dump(mode="json", exclude={"warm_s"})
    if memory is not None:  # only jobs of learning agents
        identity["memory"] = memory.identity()
    if episode_clock is not None and episode_clock.mode != "real":  # ids of real-clock jobs stay as they were
        identity["episode_clock"] = episode_clock.model_dump(mode="json")
    return identity_id(identity)


class EpisodeMatrix(BaseModel):
    """What an episode sweep plans: the matrix model x mode x seed x task, and what every job of it shares."""

    model_config = ConfigDict(frozen=True)

    models: list[ModelSpec | None]
    """None: a scripted agent's one model-less column."""

    modes: list[Mode]
    agent: AgentRef
    tasks: list[TaskContent]
    seeds: list[int]
    max_steps: int | dict[Mode, int]
    """One step limit, or one per mode."""

    observation: ObservationSettings | None = None
    """How primitive observations are made (default: the defaults)."""

    llm: LLMSettings | None = None
    project_limits: ProjectLimits | None = None
    harness: str | None = None
    """The harness digest jobs are planned under (default: this checkout's, for this kind)."""

    synthetic: SyntheticEpisodes | None = None
    agent_code: str | None = None
    extra_models: list[ModelSpec] = []
    memory: MemorySettings | None = None
    memory_sources: dict[tuple[str, Mode], str] = {}
    """Offline memory's source digest per (model name, mode)."""

    episode_clock: EpisodeClock | None = None
    model_cache: ModelCacheSettings | None = None
    """Handed to every job (it does not change their ids)."""

    record: RecordSettings = RecordSettings()
    """Handed to every job (it does not change their ids)."""


def plan_jobs(matrix: EpisodeMatrix) -> Iterator[JobSpec]:
    """The matrix in a stable order: model, mode, seed, then suite order of tasks.

    With ``memory``, each (model, mode, seed) is a stream whose tasks fall into waves."""
    limits = matrix.project_limits or ProjectLimits()
    clock = matrix.episode_clock or EpisodeClock()
    harness = matrix.harness or kind_fingerprint(harness_fingerprint(), "tasks").digest
    waves = (
        task_waves([content.task.id for content in matrix.tasks], matrix.memory) if matrix.memory is not None else {}
    )
    for model in matrix.models:
        for mode in matrix.modes:
            steps = matrix.max_steps if isinstance(matrix.max_steps, int) else matrix.max_steps[mode]
            settings = (matrix.observation or ObservationSettings()) if mode == "primitive" else None
            protocol = (matrix.llm or LLMSettings()) if model is not None else None
            for seed in matrix.seeds:
                for content in matrix.tasks:
                    task = content.task
                    stand_in = (
                        matrix.synthetic if matrix.synthetic is not None and matrix.synthetic.covers(task.id) else None
                    )
                    placement = None
                    if matrix.memory is not None:
                        label = model.name if model is not None else NO_MODEL
                        source = matrix.memory_sources.get((label, mode))
                        store = store_name(label, mode, seed)
                        placement = MemoryPlacement(
                            store=store, wave=waves[task.id], settings=matrix.memory, source=source
                        )
                    name = job_id(
                        *(model, mode, matrix.agent, content.task_hash, task.id, seed, steps, settings, protocol),
                        *(limits, harness, stand_in, matrix.agent_code, placement, clock),
                    )
                    yield JobSpec(
                        job_id=name,
                        model=model,
                        agent=matrix.agent,
                        agent_code=matrix.agent_code,
                        task_id=task.id,
                        category=task.category,
                        task_hash=content.task_hash,
                        seed=seed,
                        llm=protocol,
                        harness=harness,
                        extra_models=list(matrix.extra_models),
                        memory=placement,
                        model_cache=matrix.model_cache,
                        body=EpisodeBody(
                            mode=mode,
                            max_steps=steps,
                            observation=settings,
                            project_limits=limits,
                            episode_clock=clock,
                            record=matrix.record,
                        ),
                    )
