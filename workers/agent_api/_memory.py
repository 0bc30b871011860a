"""Memory for learning agents (AWM-style): the snapshot an episode reads, what it proposes, how it is induced.

An agent that declares ``learns = True`` reads ``context.memory.text`` at start and, at the end of
an episode, proposes what it may learn from with ``context.memory.propose(content,
judged_success=...)``: the judgement is the agent's own (e.g. a self-evaluation call by its
model), since the agent never learns the verdict. Between waves the harness calls the class's
``induce`` with the items judged worth learning from, and its answer becomes the next snapshot. (What an episode
holds of its memory, ``AgentMemory``, is part of the agent's context: ``workers.agent_api._context``.)
"""

from __future__ import annotations

from typing import ClassVar, Protocol, runtime_checkable

from pydantic import BaseModel, ConfigDict, Field

from workers.agent_api._agent import Agent
from workers.agent_api._context import ModelHandle
from workers.contract import MemoryItem, Mode


class InductionRequest(BaseModel):
    """What one induction learns from: every item of the stream judged worth learning from so far."""

    model_config = ConfigDict(frozen=True)

    mode: Mode
    store: str
    wave: int
    """The wave the induced memory is for."""

    items: list[MemoryItem]
    """In a stable order (wave, then job id), so a seeded sample is reproducible."""

    seed: int
    """Seed for any sampling the induction does (derived from the sweep's memory seed, store and wave)."""


class MemoryUpdate(BaseModel):
    """An induction's answer: the new memory text and the items it was made from."""

    model_config = ConfigDict(frozen=True)

    text: str
    sources: list[str] = Field(default_factory=list)
    """Job ids of the items used (logged with the snapshot)."""


@runtime_checkable
class LearningAgent(Agent, Protocol):
    """An agent whose memory grows across the jobs of a sweep (the sweep's ``memory`` section)."""

    learns: ClassVar[bool]

    @classmethod
    async def induce(cls, params: BaseModel, request: InductionRequest, model: ModelHandle) -> MemoryUpdate:
        """The next memory, from ``request.items``; ``model`` is the stream's model, called through the harness."""
        ...
