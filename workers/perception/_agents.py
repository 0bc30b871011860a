"""Who answers a perception item: the ``llm`` agent, and two scripted ones that test the benchmark itself.

- ``oracle`` answers with the item's label, in the strict form: both scorings must give it 100%.
- ``always_yes`` answers YES to every item, value items included: it scores the share of YES labels,
  the floor a model must clear to show it perceives anything.
- ``llm`` asks the job's model once, with the screenshot, and answers with its raw reply.

The label reaches only the scripted agents (``PerceptionQuestion.label``); the model's prompt is built
from the question, the answer's form and the screenshot alone.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

from workers.agents._model_calls import EpisodeModels
from workers.contract import YES, AgentRef, AgentUnavailableError, AnswerFormat, ModelSpec, ValueKind
from workers.perception._prompts import perception_messages
from workers.perception._refs import checked_perception_agent


@dataclass(frozen=True)
class PerceptionQuestion:
    """What an agent is asked (``label`` only reaches the scripted agents, which are the harness's own)."""

    item_id: str
    question: str
    answer_format: AnswerFormat
    value_kind: ValueKind | None
    screenshot_png: bytes
    label: str | None = None


class PerceptionAgent(Protocol):
    needs_model: bool

    async def answer(self, question: PerceptionQuestion, model: ModelSpec | None, models: EpisodeModels) -> str: ...


class OraclePerceptionAgent:
    needs_model = False

    async def answer(self, question: PerceptionQuestion, model: ModelSpec | None, models: EpisodeModels) -> str:
        if question.label is None:
            raise AgentUnavailableError("the perception oracle needs the item's label")
        return question.label


class AlwaysYesAgent:
    needs_model = False

    async def answer(self, question: PerceptionQuestion, model: ModelSpec | None, models: EpisodeModels) -> str:
        return YES


class LLMPerceptionAgent:
    needs_model = True

    async def answer(self, question: PerceptionQuestion, model: ModelSpec | None, models: EpisodeModels) -> str:
        if model is None:
            raise AgentUnavailableError("the llm perception agent needs a model")
        messages = perception_messages(
            question.question, question.answer_format, question.value_kind, question.screenshot_png
        )
        reply = await models.connect(model).complete(messages)
        return reply.text


def perception_agent(ref: AgentRef) -> PerceptionAgent:
    """The perception agent a job names (``AgentUnavailableError`` names the problem)."""
    checked_perception_agent(ref)
    agents: dict[str, PerceptionAgent] = {
        "oracle": OraclePerceptionAgent(),
        "always_yes": AlwaysYesAgent(),
        "llm": LLMPerceptionAgent(),
    }
    return agents[ref.name]
