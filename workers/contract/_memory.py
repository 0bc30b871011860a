"""Memory shared across the jobs of a sweep (what AWM-style agents learn from), as plain data.

A learning agent reads one **snapshot** of its memory at the start of an episode and proposes
**items** at its end, each with its own judgement of success. The driver keeps one store per
(model, mode, seed) stream and induces the next snapshot between **waves** of jobs; which items
count is the agent's judgement, never the evaluation's verdict, unless the sweep asks for the
labelled ground-truth ablation.
"""

from __future__ import annotations

import hashlib
from pathlib import Path
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, JsonValue, model_validator

MemoryKind = Literal["online", "offline"]
LearnFrom = Literal["self_judgement", "verdict_ablation"]


class MemorySettings(BaseModel):
    """The sweep's ``memory`` section: how a learning agent's memory grows (part of every job's identity)."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    kind: MemoryKind = "online"
    """``online``: learn from this sweep's own jobs, wave after wave; ``offline``: induce once from the
    items of a previous run directory (``from_run``) and never update."""

    wave_size: int = Field(default=5, ge=1)
    """Jobs per wave of a stream (online): wave k+1 starts once wave k is decided and induced from."""

    order: Literal["suite", "shuffled"] = "suite"
    """The order tasks enter waves: the suite's, or shuffled with ``seed``."""

    seed: int = 0
    """Seeds the task shuffle and each induction's sampling."""

    learn_from: LearnFrom = "self_judgement"
    """What makes an item worth learning from: the agent's own judgement, or (``verdict_ablation``, an
    explicitly labelled ablation that leaks the tests into memory) the evaluation's verdict."""

    from_run: Path | None = None
    """Offline: the run directory whose items seed the memory."""

    @model_validator(mode="after")
    def _source_fits_kind(self) -> MemorySettings:
        if self.kind == "offline" and self.from_run is None:
            raise ValueError("offline memory needs from_run: the run directory to learn from")
        if self.kind == "online" and self.from_run is not None:
            raise ValueError("from_run is for offline memory; online memory learns from this sweep")
        return self

    def identity(self) -> dict[str, object]:
        """What changes what jobs see (the source folder's path does not; its items' digest does)."""
        return self.model_dump(mode="json", exclude={"from_run"})


class MemoryPlacement(BaseModel):
    """Where a job stands in its memory stream (planned, part of the job's identity)."""

    model_config = ConfigDict(frozen=True)

    store: str
    """The stream's store: one per (model, mode, seed) of the sweep."""

    wave: int = Field(ge=0)
    settings: MemorySettings
    source: str | None = None
    """Offline: digest of the items the memory is induced from."""

    def identity(self) -> dict[str, object]:
        return {"store": self.store, "wave": self.wave, "settings": self.settings.identity(), "source": self.source}


class MemorySnapshot(BaseModel):
    """What a learning agent is shown of its memory in one episode."""

    model_config = ConfigDict(frozen=True)

    store: str
    wave: int
    text: str = ""
    """The memory's content (AWM: the induced workflows); empty before anything was learnt."""

    sources: list[str] = Field(default_factory=list)
    """Job ids of the items the text was induced from."""

    @property
    def digest(self) -> str:
        """The hash each job records: equal texts are equal memories, whichever wave made them."""
        return memory_digest(self.text)


class MemoryItem(BaseModel):
    """Something an agent proposes to learn from one episode, with its own judgement of success."""

    model_config = ConfigDict(frozen=True)

    source: str = ""
    """The job id (set by the harness)."""

    task_id: str = ""
    judged_success: bool
    content: JsonValue
    """The agent's own record (AWM: the instruction and the thought/action trail)."""


def memory_digest(text: str) -> str:
    return hashlib.sha256(text.encode()).hexdigest()[:16]
