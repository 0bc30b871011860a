"""The ``awm`` agent: the llm agent plus Agent Workflow Memory, in both modes.

Each episode starts with the workflows induced so far in its system prompt (the sweep's
``memory`` section: online waves or offline from a previous run). When the episode ends, the
agent's own model judges whether the task was accomplished (it never learns the verdict) and
the thought/action trail is proposed with that judgement. Between waves, ``induce`` samples at
most ``sample_size`` of the trails judged successful (seeded) and asks the model for workflows.
"""

from __future__ import annotations

import random
from typing import Any, ClassVar

from pydantic import BaseModel, ConfigDict, Field, ValidationError

from workers.agent_api import EpisodeEnd, InductionRequest, MemoryUpdate, ModelHandle, StepResult, TaskContext
from workers.agents._awm_prompts import (
    Trail,
    induction_prompt,
    judge_messages,
    judged_success,
    trail_lines,
    workflows_of,
)
from workers.agents._llm_agent import LLMAgent
from workers.contract import (
    Action,
    CompositeAction,
    Done,
    Failed,
    ModelCallError,
    Observation,
    PrimitiveAction,
)


class AWMParams(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)

    sample_size: int = Field(default=10, ge=1)
    """Successful trails one induction reads at most (AWM: 10), sampled with the induction's seed."""


class AWMAgent(LLMAgent):
    """Acts like the llm agent with its workflow memory in the system prompt, judges itself, proposes its trail."""

    Params: ClassVar[type[BaseModel]] = AWMParams
    learns: ClassVar[bool] = True

    async def start(self, context: TaskContext) -> None:
        self.context = context
        self._actions: list[dict[str, Any]] = []
        self._trail: list[str] = []
        self._last: Observation | None = None
        self._last_reply = ""
        await super().start(context)

    async def system_text(self, context: TaskContext, workflows: str = "") -> str:
        return await super().system_text(context, workflows=context.memory.text)

    async def act(self, observation: Observation | None, last: StepResult | None) -> Action:
        self._last = observation
        action = await super().act(observation, last)
        self._last_reply = str(self._history[-1]["content"])
        done = _as_json(action)
        if done is not None:
            self._actions.append(done)
        self._trail.append(trail_lines(_thought(self._last_reply), done))
        return action

    async def finish(self, end: EpisodeEnd) -> None:
        if self.context is None or not hasattr(self, "model"):  # it never got going: nothing to learn from
            return
        messages = judge_messages(self.mode, self.context.instruction, self._actions, self._last_reply, self._last)
        try:
            success = judged_success((await self.model.complete(messages)).text)
        except ModelCallError:  # no judgement is a failure, as in AWM
            success = False
        trail = Trail(task=self.context.instruction, trajectory="\n".join(line for line in self._trail if line))
        self.context.memory.propose(trail.model_dump(), judged_success=success)

    @classmethod
    async def induce(cls, params: BaseModel, request: InductionRequest, model: ModelHandle) -> MemoryUpdate:
        assert isinstance(params, AWMParams)
        trails: list[tuple[str, Trail]] = []
        for item in request.items:
            try:
                trails.append((item.source, Trail.model_validate(item.content)))
            except ValidationError:
                continue  # not a trail of this agent's: nothing to learn from it
        if not trails:
            return MemoryUpdate(text="")
        sample = random.Random(request.seed).sample(trails, min(params.sample_size, len(trails)))
        reply = await model.complete(
            [{"role": "user", "content": induction_prompt(request.mode, [t for _, t in sample])}]
        )
        return MemoryUpdate(text=workflows_of(reply.text), sources=[source for source, _ in sample])


def _as_json(action: Action) -> dict[str, Any] | None:
    if isinstance(action, CompositeAction | PrimitiveAction):
        return {"api": action.api, "args": action.args}
    if isinstance(action, Done | Failed):
        return {"api": action.name, "args": {}}
    return None  # a reply without a usable action


def _thought(reply: str) -> str:
    text = reply.split("```", 1)[0].strip()
    return text.removeprefix("Analysis:").strip()
