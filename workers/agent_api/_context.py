"""What an agent is given at the start of an episode: the task, the means to call models, and its memory.

Every model call goes through the harness's own client: retries, the cluster-wide rate
limiter, the circuit breaker, token and cost accounting, and the trajectory log (what each
step sent and received) apply to a plugin's calls exactly as to the built-in ``llm`` agent.
"""

from __future__ import annotations

from collections.abc import Awaitable, Callable
from dataclasses import dataclass
from typing import Any, Protocol

from pydantic import BaseModel, ConfigDict, JsonValue

from workers.contract import (
    AgentUnavailableError,
    CompositeAction,
    LLMSettings,
    MemoryItem,
    MemorySnapshot,
    Mode,
    ModelSpec,
)


class ModelReply(BaseModel):
    """A model's answer to one call, and what it cost."""

    model_config = ConfigDict(frozen=True)

    text: str
    input_tokens: int
    output_tokens: int
    cost_usd: float
    latency_s: float
    cached: bool = False
    """Answered from the sweep's model cache (a reply this request got before; it cost nothing)."""


class ModelHandle(Protocol):
    """One model, called through the harness (raises ``ModelCallError`` when a call fails for good)."""

    spec: ModelSpec

    async def complete(self, messages: list[dict[str, Any]]) -> ModelReply:
        """OpenAI-style chat messages (images as ``image_url`` data URLs), sent with the episode's seed and
        the model's own parameters (temperature, max_tokens, ...: part of the job's identity)."""
        ...


@dataclass(frozen=True)
class Privileges:
    """What only a privileged agent (an oracle) may read: the task's solution and the live editor."""

    initial_project: bytes
    golden_project: bytes | None
    golden_trajectory: list[CompositeAction] | None
    editor: Any  # a workers.editor.Editor; typed loosely so that this API loads no browser stack
    """The page the episode runs in (for oracles that plan gestures from what it shows)."""


class AgentMemory:
    """A learning agent's memory within one episode."""

    def __init__(self, snapshot: MemorySnapshot | None, job_id: str, task_id: str) -> None:
        self.snapshot = snapshot
        self._job_id = job_id
        self._task_id = task_id
        self.items: list[MemoryItem] = []

    @property
    def text(self) -> str:
        """The memory as induced so far ("" before anything was learnt, or in a sweep without memory)."""
        return self.snapshot.text if self.snapshot is not None else ""

    def propose(self, content: JsonValue, *, judged_success: bool) -> None:
        """Offer this episode's record for later inductions, with the agent's own judgement of success."""
        self.items.append(
            MemoryItem(source=self._job_id, task_id=self._task_id, judged_success=judged_success, content=content)
        )


class TaskContext:
    """The task as an agent may see it, the step budget and seed, and handles on models."""

    def __init__(
        self,
        *,
        task_id: str,
        category: str,
        instruction: str,
        mode: Mode,
        max_steps: int,
        seed: int,
        block_catalog: Callable[[], Awaitable[str | None]],
        model: ModelSpec | None,
        connect: Callable[[ModelSpec], ModelHandle],
        llm: LLMSettings | None = None,
        privileges: Privileges | None = None,
        memory: AgentMemory | None = None,
    ) -> None:
        self.task_id = task_id
        self.category = category
        self.instruction = instruction
        self.mode: Mode = mode
        self.max_steps = max_steps
        self.seed = seed
        self._block_catalog = block_catalog
        self._blocks: str | None = None
        self.llm = llm or LLMSettings()
        """The sweep's ``llm`` settings: the conversation protocol of the built-in llm agent, for
        agents that converse the same way (history window, screenshots kept, action results shown)."""

        self._model = model
        self._connect = connect
        self._privileges = privileges
        self._memory = memory

    async def block_catalog(self) -> str | None:
        """The blocks the composite API can create, one line each (None in primitive mode, where the
        palette shows them); read from the editor on first use."""
        if self._blocks is None:
            self._blocks = await self._block_catalog()
        return self._blocks

    def model(self, spec: ModelSpec | None = None) -> ModelHandle:
        """The job's model (the sweep's ``models`` entry), or another one an agent's params name."""
        spec = spec or self._model
        if spec is None:
            raise AgentUnavailableError("this job has no model: the agent must declare needs_model = True")
        return self._connect(spec)

    @property
    def memory(self) -> AgentMemory:
        """The memory shared across the sweep's jobs (see ``LearningAgent``): read ``text``, ``propose`` items."""
        if self._memory is None:
            self._memory = AgentMemory(None, "", self.task_id)
        return self._memory

    @property
    def privileges(self) -> Privileges:
        """The solution and the editor; only for agents that declare ``privileged = True``."""
        if self._privileges is None:
            raise AgentUnavailableError("only privileged agents (oracles) may read the solution or the editor")
        return self._privileges
