"""Planning: the job matrix model x mode x task x seed, each job named by what decides its outcome.

A job id is a hash of everything that can change the job's result (model and its parameters,
mode, agent, the task's content, seed, step limit, harness version), so a changed task or config
is a new job and a stale result is never reused; identical jobs keep their id across runs,
which is what resume relies on.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Iterator, Mapping
from importlib.metadata import version

from pydantic import BaseModel, ConfigDict

from scratchworld_dist.suites import Task
from workers import (
    AgentName,
    EpisodeSpec,
    EvaluationClock,
    EvaluationProfile,
    LLMSettings,
    Mode,
    ModelSpec,
    ObservationSettings,
    TaskPayload,
)

HARNESS_VERSION = version("scratchworld-dist")
"""Recorded with every job; bump the package version when a change can alter verdicts."""

NO_MODEL = "-"
"""Model label of scripted agents (oracle, noop) that call no model."""


class JobSpec(BaseModel):
    """One cell of the matrix, as planned by the driver."""

    model_config = ConfigDict(frozen=True)

    job_id: str
    model: ModelSpec | None
    mode: Mode
    agent: AgentName
    task_id: str
    category: str
    task_hash: str
    seed: int
    max_steps: int
    observation: ObservationSettings | None = None
    """How primitive observations are made (None in composite mode)."""

    llm: LLMSettings | None = None
    """The llm agent's conversation protocol (None for scripted agents)."""

    @property
    def model_name(self) -> str:
        return self.model.name if self.model is not None else NO_MODEL

    def episode(self, attempt: int, timeout_s: float) -> EpisodeSpec:
        return EpisodeSpec(
            job_id=self.job_id,
            attempt=attempt,
            task_id=self.task_id,
            mode=self.mode,
            agent=self.agent,
            model=self.model,
            seed=self.seed,
            max_steps=self.max_steps,
            observation=self.observation,
            llm=self.llm,
            timeout_s=timeout_s,
        )


class TaskContent(BaseModel):
    """A task read into memory: its payload for workers and the hash of all of it."""

    model_config = ConfigDict(frozen=True)

    task: Task
    payload: TaskPayload
    task_hash: str


def read_task(
    task: Task, profile: EvaluationProfile | None = None, clock: EvaluationClock | None = None
) -> TaskContent:
    """Read a task's files once; the hash covers every byte a worker will see (and profile and clock)."""
    spec = task.evaluation_spec(profile, clock)
    golden = task.golden_project.read_bytes() if task.golden_project is not None else None
    trajectory = task.trajectory()
    payload = TaskPayload(
        task_id=task.id,
        category=task.category,
        instruction=task.instruction,
        initial_project=task.initial_project.read_bytes(),
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


def suite_hash(contents: list[TaskContent]) -> str:
    """One hash for the selected tasks' contents (order-independent)."""
    digest = hashlib.sha256()
    for task_hash in sorted(c.task_hash for c in contents):
        digest.update(task_hash.encode())
    return digest.hexdigest()[:16]


def job_id(
    model: ModelSpec | None,
    mode: str,
    agent: str,
    task_hash: str,
    task_id: str,
    seed: int,
    max_steps: int,
    observation: ObservationSettings | None = None,
    llm: LLMSettings | None = None,
) -> str:
    identity: dict[str, object] = {
        "model": None if model is None else model.identity(),
        "mode": mode,
        "agent": agent,
        "task": [task_id, task_hash],
        "seed": seed,
        "max_steps": max_steps,
        "harness": HARNESS_VERSION,
    }
    if observation is not None:  # only primitive jobs have one, so composite ids stay as they were
        identity["observation"] = observation.model_dump(mode="json")
    if llm is not None:  # only llm jobs have one
        identity["llm"] = llm.identity()
    canonical = json.dumps(identity, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(canonical.encode()).hexdigest()[:24]


def plan_jobs(
    models: list[ModelSpec | None],
    modes: list[Mode],
    agent: AgentName,
    tasks: list[TaskContent],
    seeds: list[int],
    max_steps: int | Mapping[Mode, int],
    observation: ObservationSettings | None = None,
    llm: LLMSettings | None = None,
) -> Iterator[JobSpec]:
    """The matrix in a stable order: model, mode, seed, then suite order of tasks."""
    for model in models:
        for mode in modes:
            steps = max_steps if isinstance(max_steps, int) else max_steps[mode]
            settings = (observation or ObservationSettings()) if mode == "primitive" else None
            protocol = (llm or LLMSettings()) if agent == "llm" else None
            for seed in seeds:
                for content in tasks:
                    task = content.task
                    yield JobSpec(
                        job_id=job_id(model, mode, agent, content.task_hash, task.id, seed, steps, settings, protocol),
                        model=model,
                        mode=mode,
                        agent=agent,
                        task_id=task.id,
                        category=task.category,
                        task_hash=content.task_hash,
                        seed=seed,
                        max_steps=steps,
                        observation=settings,
                        llm=protocol,
                    )
