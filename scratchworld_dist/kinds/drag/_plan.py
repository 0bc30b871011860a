"""Planning the drag benchmark: its section of a sweep config (``drag:``: its own axes and the agents it compares),
and the job matrix model x setting x task x seed, named by what decides each job.

A drag job's id hashes the model and its parameters, the setting, the agent, the task's content
(project bytes, source, connection, view), the seed, the element list and its observation
settings, the conversation protocol and the harness fingerprint (the editor's geometry decides
the regions), and a plugin agent's code, so resume never reuses a drag made under other conditions.
"""

from __future__ import annotations

import hashlib
from collections.abc import Iterator
from pathlib import Path
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field, field_validator

from scratchworld_dist.kinds._single_answer import AgentsSection, checked_agents
from scratchworld_dist.kinds.drag.items import DragTask
from scratchworld_dist.sweep import JobBody, JobSpec, agent_identity, identity_id, read_project
from workers.agent_api import DragSetting, agent_class, agent_code
from workers.contract import (
    AgentRef,
    ConnectionKind,
    LLMSettings,
    ModelCacheSettings,
    ModelSpec,
    ObservationSettings,
    ProjectLimits,
)
from workers.kinds import kind_fingerprint
from workers.kinds.drag import DragPayload, DragType
from workers.node import harness_fingerprint

DRAG_MODE = "primitive"
"""The mode column of drag jobs: a drag is a primitive-mode gesture, diagnosed in isolation."""


class DragTaskInfo(BaseModel):
    """What reports group a drag job by (its task's type, connection kind and source)."""

    model_config = ConfigDict(frozen=True)

    type: DragType
    connection: ConnectionKind
    source: Literal["canvas", "flyout"]


class DragBody(JobBody):
    """A drag job's own settings: the setting it is asked under, its task as reports group it, whether the
    element list is shown and how it is made, what project it may load."""

    kind: Literal["drag"] = "drag"
    setting: DragSetting
    task: DragTaskInfo
    element_list: bool = False
    observation: ObservationSettings | None = None
    """How the element list is made (None without one)."""

    project_limits: ProjectLimits = ProjectLimits()

    def columns(self) -> dict[str, Any]:
        return {"mode": DRAG_MODE, "max_steps": 1, "setting": self.setting}


class DragContent(BaseModel):
    """A drag task read into memory: its payload for workers and the hash of all of it."""

    model_config = ConfigDict(frozen=True)

    task: DragTask
    payload: DragPayload
    task_hash: str


def read_drag_task(task: DragTask, limits: ProjectLimits | None = None) -> DragContent:
    """Read a drag task's project once (checked against ``limits``); the hash covers all a worker sees."""
    payload = task.payload(read_project(task.initial_project, limits or ProjectLimits()))
    digest = hashlib.sha256(payload.initial_project)
    digest.update(payload.model_dump_json(exclude={"initial_project"}).encode())
    return DragContent(task=task, payload=payload, task_hash=digest.hexdigest()[:16])


def drag_job_id(
    model: ModelSpec | None,
    setting: DragSetting,
    agent: AgentRef,
    content: DragContent,
    seed: int,
    *,
    element_list: bool,
    observation: ObservationSettings | None,
    llm: LLMSettings | None,
    project_limits: ProjectLimits,
    harness: str,
    code: str | None = None,
) -> str:
    identity: dict[str, object] = {
        "benchmark": "drag",
        "model": None if model is None else model.identity(),
        "setting": setting,
        "agent": agent_identity(agent, code),
        "task": [content.task.id, content.task_hash],
        "seed": seed,
        "element_list": element_list,
        "observation": None if observation is None else observation.model_dump(mode="json"),
        "llm": None if llm is None else llm.identity(),
        "project_limits": project_limits.model_dump(mode="json"),
        "harness": harness,
    }
    return identity_id(identity)


def plan_drag_jobs(
    models: list[ModelSpec | None],
    settings: list[DragSetting],
    agents: AgentRef | list[AgentRef],
    contents: list[DragContent],
    seeds: list[int],
    *,
    element_list: bool = False,
    observation: ObservationSettings | None = None,
    llm: LLMSettings | None = None,
    project_limits: ProjectLimits | None = None,
    harness: str | None = None,
    model_cache: ModelCacheSettings | None = None,
) -> Iterator[JobSpec]:
    """The matrix in a stable order: agent, model, setting, seed, then suite order of tasks. A scripted agent
    (one that needs no model) runs once, without a model, whatever ``models`` holds."""
    limits = project_limits or ProjectLimits()
    harness = harness or kind_fingerprint(harness_fingerprint(), "drag").digest
    shown = (observation or ObservationSettings()) if element_list else None
    found = [(who, agent_class(who.name, "drag")) for who in ([agents] if isinstance(agents, AgentRef) else agents)]
    cells = [(who, cls, model) for who, cls in found for model in (models if cls.needs_model else [None])]
    for agent, cls, model in cells:
        code = agent_code(cls)
        protocol = (llm or LLMSettings()) if model is not None else None
        for setting in settings:
            for seed in seeds:
                for content in contents:
                    task = content.task
                    name = drag_job_id(
                        model,
                        setting,
                        agent,
                        content,
                        seed,
                        element_list=element_list,
                        observation=shown,
                        llm=protocol,
                        project_limits=limits,
                        harness=harness,
                        code=code,
                    )
                    info = DragTaskInfo(type=task.type, connection=task.connection.kind, source=task.source.kind)
                    yield JobSpec(
                        job_id=name,
                        model=model,
                        agent=agent,
                        agent_code=code,
                        task_id=task.id,
                        category=task.type,
                        task_hash=content.task_hash,
                        seed=seed,
                        llm=protocol,
                        harness=harness,
                        model_cache=model_cache,
                        body=DragBody(
                            setting=setting,
                            task=info,
                            element_list=element_list,
                            observation=shown,
                            project_limits=limits,
                        ),
                    )


class DragSweep(AgentsSection):
    """The drag benchmark's own axes (``benchmark: drag``): jobs are model x setting x task x seed."""

    model_config = ConfigDict(extra="forbid")

    settings: list[DragSetting] = Field(default_factory=lambda: ["baseline"], min_length=1)
    types: list[DragType] = Field(default_factory=list)
    """Task types to run (empty: both)."""

    agents: list[AgentRef] = Field(default_factory=list)
    """The drag agents to compare in one sweep (default: the config's ``agent``); a scripted one runs once,
    without the models, a model-driven one once per model."""

    element_list: bool = False
    """Show primitive mode's element list with the screenshot, and accept ``<index>`` answers."""

    optional_suites: list[Path] = Field(default_factory=list)
    """More drag suites, each run when present and skipped with a notice when not (e.g. an upstream clone)."""

    @field_validator("settings")
    @classmethod
    def _distinct(cls, value: list[DragSetting]) -> list[DragSetting]:
        if len(set(value)) != len(value):
            raise ValueError("settings must be distinct")
        return value

    @field_validator("agents")
    @classmethod
    def _known_agents(cls, agents: list[AgentRef]) -> list[AgentRef]:
        return checked_agents(agents, "drag")
