"""Planning the perception benchmark: its section of a sweep config (``perception:``: the question kinds and the
agents it compares), and the job matrix agent x model x item x seed, named by what decides each job.

A perception job's id hashes the model and its parameters, the agent, the item's content (its question,
answer, form and the screenshot's bytes), the seed, the conversation protocol, the harness fingerprint
(the prompt and the scoring are worker code) and a plugin agent's code, so resume never reuses an answer
given under other conditions.
"""

from __future__ import annotations

import hashlib
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field, field_validator

from scratchworld_dist._errors import ConfigError
from scratchworld_dist.kinds._single_answer import AgentsSection, checked_agents
from scratchworld_dist.kinds.perception.items import (
    PerceptionItem,
    PerceptionSuite,
    load_perception_suite,
    read_screenshot,
)
from scratchworld_dist.sweep import JobBody, JobSpec, agent_identity, identity_id, present_suites, wanted_ids
from workers.agent_api import AnswerFormat, ValueKind, agent_class, agent_code
from workers.contract import AgentRef, LLMSettings, ModelCacheSettings, ModelSpec
from workers.kinds import kind_fingerprint
from workers.kinds.perception import PerceptionPayload, QuestionKind
from workers.node import harness_fingerprint

PERCEPTION_MODE = "primitive"
"""The mode column of perception jobs: a screenshot is what primitive mode observes, read here in isolation."""


class PerceptionItemInfo(BaseModel):
    """What reports group a perception job by (its item's kind, tag and form of answer), and its question."""

    model_config = ConfigDict(frozen=True)

    question: str
    kind: QuestionKind
    tag: str
    answer_format: AnswerFormat
    value_kind: ValueKind | None = None


class PerceptionBody(JobBody):
    """A perception job's own part: the item it asks about, as reports group it."""

    kind: Literal["perception"] = "perception"
    item: PerceptionItemInfo

    def columns(self) -> dict[str, Any]:
        return {"mode": PERCEPTION_MODE, "max_steps": 1}


class PerceptionContent(BaseModel):
    """An item read into memory: its payload for workers and the hash of all of it."""

    model_config = ConfigDict(frozen=True)

    task: PerceptionItem
    payload: PerceptionPayload
    task_hash: str


class PerceptionSelection(BaseModel):
    """The items a perception sweep runs, from the suites that were there."""

    model_config = ConfigDict(frozen=True)

    name: str
    kind: str
    root: Path
    contents: list[PerceptionContent]


def read_perception_item(item: PerceptionItem) -> PerceptionContent:
    """Read an item's screenshot once (checked to be a PNG); the hash covers all a worker sees."""
    payload = item.payload(read_screenshot(item.screenshot))
    digest = hashlib.sha256(payload.screenshot_png)
    digest.update(payload.model_dump_json(exclude={"screenshot_png"}).encode())
    return PerceptionContent(task=item, payload=payload, task_hash=digest.hexdigest()[:16])


def select_perception_items(
    suite: Path,
    optional_suites: Sequence[Path],
    ids: Sequence[str],
    kinds: Sequence[QuestionKind],
    say: Callable[[str], None],
) -> PerceptionSelection:
    """The items of ``suite`` and of each optional suite that is present, selected by ``ids`` and ``kinds``.

    A problem in a suite (an item left out) is said, not fatal; ids shared between suites, ids naming no
    item and an empty selection are ``ConfigError``.
    """
    suites: list[PerceptionSuite] = present_suites(
        suite, optional_suites, load_perception_suite, say, benchmark="perception", item="item"
    )
    for loaded in suites:
        for problem in loaded.problems:
            say(f"perception: {loaded.name}: {problem} (left out)")
    items = [item for loaded in suites for item in loaded.items]
    wanted = wanted_ids([item.id for item in items], ids, benchmark="perception", item="item", suites=suites)
    chosen = [i for i in items if (not wanted or i.id in wanted) and (not kinds or i.kind in kinds)]
    if not chosen:
        raise ConfigError(f"the selection matches no perception item of {', '.join(s.name for s in suites)}")
    return PerceptionSelection(
        name=" + ".join(s.name for s in suites),
        kind=suites[0].kind,
        root=suites[0].root,
        contents=[read_perception_item(item) for item in chosen],
    )


def perception_job_id(
    model: ModelSpec | None,
    agent: AgentRef,
    content: PerceptionContent,
    seed: int,
    *,
    llm: LLMSettings | None,
    harness: str,
    code: str | None = None,
) -> str:
    identity: dict[str, object] = {
        "benchmark": "perception",
        "model": None if model is None else model.identity(),
        "agent": agent_identity(agent, code),
        "task": [content.task.id, content.task_hash],
        "seed": seed,
        "llm": None if llm is None else llm.identity(),
        "harness": harness,
    }
    return identity_id(identity)


def plan_perception_jobs(
    models: list[ModelSpec | None],
    agents: list[AgentRef],
    contents: list[PerceptionContent],
    seeds: list[int],
    *,
    llm: LLMSettings | None = None,
    harness: str | None = None,
    model_cache: ModelCacheSettings | None = None,
) -> Iterator[JobSpec]:
    """The matrix in a stable order: agent, model, seed, then suite order of items. A scripted agent (one
    that needs no model) runs once, without a model, whatever ``models`` holds."""
    harness = harness or kind_fingerprint(harness_fingerprint(), "perception").digest
    found = [(who, agent_class(who.name, "perception")) for who in agents]
    cells = [(who, cls, model) for who, cls in found for model in (models if cls.needs_model else [None])]
    for agent, cls, model in cells:
        code = agent_code(cls)
        protocol = (llm or LLMSettings()) if model is not None else None
        for seed in seeds:
            for content in contents:
                item = content.task
                yield JobSpec(
                    job_id=perception_job_id(model, agent, content, seed, llm=protocol, harness=harness, code=code),
                    model=model,
                    agent=agent,
                    agent_code=code,
                    task_id=item.id,
                    category=item.kind,
                    task_hash=content.task_hash,
                    seed=seed,
                    llm=protocol,
                    harness=harness,
                    model_cache=model_cache,
                    body=PerceptionBody(
                        item=PerceptionItemInfo(
                            question=item.question,
                            kind=item.kind,
                            tag=item.tag,
                            answer_format=item.answer_format,
                            value_kind=item.value_kind,
                        )
                    ),
                )


class PerceptionSweep(AgentsSection):
    """The perception benchmark's own axes (``benchmark: perception``): jobs are agent x model x item x seed."""

    model_config = ConfigDict(extra="forbid")

    agents: list[AgentRef] = Field(default_factory=list)
    """The perception agents to compare in one sweep (default: the config's ``agent``); a scripted one
    (oracle, always_yes) runs once, without the models, ``llm`` once per model."""

    kinds: list[QuestionKind] = Field(default_factory=list)
    """Item kinds to run (empty: all of connection, existence and field)."""

    optional_suites: list[Path] = Field(default_factory=list)
    """More perception suites, each run when present and skipped with a notice when not (e.g. an upstream clone)."""

    @field_validator("agents")
    @classmethod
    def _known_agents(cls, agents: list[AgentRef]) -> list[AgentRef]:
        return checked_agents(agents, "perception")
