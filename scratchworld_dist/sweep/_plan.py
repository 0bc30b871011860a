"""Planning's core: a job as the driver plans it (a header every kind shares and its kind's body), how a job
is named, and reading a project within its limits.

A job id is a hash of everything that can change the job's result (each kind says what: the model and its
parameters, the agent, the item's content, the seed, the harness fingerprint...), so a changed task, config
or harness is a new job and a stale result is never reused; identical jobs keep their id across runs,
which is what resume relies on.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any, Protocol

from pydantic import BaseModel, ConfigDict, SerializeAsAny

from scratchworld_dist._errors import ProjectFormatError, SuiteError
from scratchworld_dist._files import FileTooLargeError, read_file
from scratchworld_dist.kinds import job_kind
from workers.contract import (
    MIB,
    AgentRef,
    ClockMode,
    LLMSettings,
    MemoryPlacement,
    MemorySnapshot,
    ModelCacheSettings,
    ModelSpec,
    ProjectLimits,
    check_project,
)

NO_MODEL = "-"
"""Model label of scripted agents (oracle, noop) that call no model."""


class JobBody(BaseModel):
    """What a job of one kind has besides the header; each kind's body adds its own fields."""

    model_config = ConfigDict(frozen=True)

    kind: str
    """The job's kind (``scratchworld_dist.kinds``): what builds its worker job and its own rows."""

    def columns(self) -> dict[str, Any]:
        """Its values of the job row's columns a kind decides (``mode``, ``max_steps``, ``setting``)."""
        raise NotImplementedError

    @property
    def page_clock(self) -> ClockMode:
        """Whose time the job's page runs on, if it has one (admission measures editors under it)."""
        return "real"

    @property
    def expected_length(self) -> float:
        """How long the job may take against the other jobs of its sweep, in any unit: the longest start first
        (``scratchworld_dist._run``). A single-step job is 1."""
        return 1.0


class JobSpec(BaseModel):
    """One cell of the matrix, as planned by the driver: the header every kind shares, and its kind's body."""

    model_config = ConfigDict(frozen=True)

    job_id: str
    model: ModelSpec | None
    agent: AgentRef
    agent_code: str | None = None
    """Digest of a plugin agent's code (None for the built-in agents, which the harness fingerprint covers)."""

    task_id: str
    category: str
    task_hash: str
    seed: int
    llm: LLMSettings | None = None
    """The conversation protocol of model-driven agents (None for jobs without a model)."""

    harness: str
    """The harness fingerprint the job was planned under (part of its id)."""

    extra_models: list[ModelSpec] = []
    """Models the agent calls besides ``model`` (e.g. a grounding model), as its params name them."""

    memory: MemoryPlacement | None = None
    """The job's memory stream and wave (learning agents; part of its id)."""

    memory_snapshot: MemorySnapshot | None = None
    """The memory the job is shown: set by the driver when the job's wave starts (not part of its id)."""

    model_cache: ModelCacheSettings | None = None
    """The sweep's model cache (not part of the id: a replayed reply is the one this model gave to this
    exact request under this seed, so the job's conditions are the same; rows record the hits)."""

    body: SerializeAsAny[JobBody]
    """What the job's kind adds (an episode's mode and step limit, a drag's setting...)."""

    @property
    def benchmark(self) -> str:
        """The job's kind."""
        return self.body.kind

    @property
    def mode(self) -> str:
        """The mode its rows name (an episode's own; a single-step job's is primitive), as its body decides."""
        return str(self.body.columns()["mode"])

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

    def worker_header(self, attempt: int, timeout_s: float) -> dict[str, Any]:
        """The fields of every kind's worker job (``workers.contract.JobHeader``), for ``attempt`` within
        ``timeout_s``."""
        return {
            "job_id": self.job_id,
            "attempt": attempt,
            "task_id": self.task_id,
            "timeout_s": timeout_s,
            "harness": self.harness,
        }

    def agent_header(self, attempt: int, timeout_s: float) -> dict[str, Any]:
        """The fields of a worker job an agent acts in (``workers.contract.AgentJob``): the header, and who acts
        with which model, seed and model settings."""
        return {
            **self.worker_header(attempt, timeout_s),
            "agent": self.agent,
            "agent_code": self.agent_code,
            "model": self.model,
            "seed": self.seed,
            "llm": self.llm,
            "model_cache": self.model_cache,
        }


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


class HashedContent(Protocol):
    """A task read into memory (any kind's content model)."""

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
