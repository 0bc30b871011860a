"""Who answers a perception item: the ``llm`` agent, and two scripted ones that test the benchmark itself.

- ``oracle`` answers with the item's label, in the strict form: both scorings must give it 100%.
- ``always_yes`` answers YES to every item, value items included: it scores the share of YES labels,
  the floor a model must clear to show it perceives anything.
- ``llm`` asks the job's model once, with the screenshot, and answers with its raw reply.

The label reaches only privileged agents (``PerceptionQuestion.label``: the oracle); the model's prompt is built
from the question, the answer's form and the screenshot alone.
"""

from __future__ import annotations

from workers.agent_api import ModelSource, PerceptionAgentBase, PerceptionQuestion, build_agent
from workers.contract import AgentRef, AgentUnavailableError, ModelSpec
from workers.kinds.perception._contract import YES
from workers.kinds.perception._prompts import perception_messages

__all__ = ["AlwaysYesAgent", "LLMPerceptionAgent", "OraclePerceptionAgent", "PerceptionQuestion", "perception_agent"]


class OraclePerceptionAgent(PerceptionAgentBase):
    privileged = True

    async def answer(self, question: PerceptionQuestion, model: ModelSpec | None, models: ModelSource) -> str:
        if question.label is None:
            raise AgentUnavailableError("the perception oracle needs the item's label")
        return question.label


class AlwaysYesAgent(PerceptionAgentBase):
    async def answer(self, question: PerceptionQuestion, model: ModelSpec | None, models: ModelSource) -> str:
        return YES


class LLMPerceptionAgent(PerceptionAgentBase):
    needs_model = True

    async def answer(self, question: PerceptionQuestion, model: ModelSpec | None, models: ModelSource) -> str:
        if model is None:
            raise AgentUnavailableError("the llm perception agent needs a model")
        messages = perception_messages(
            question.question, question.answer_format, question.value_kind, question.screenshot_png
        )
        reply = await models.connect(model).complete(messages)
        return reply.text


def perception_agent(ref: AgentRef) -> PerceptionAgentBase:
    """The perception agent a job names, found in the perception agents' registry and built with its validated
    params (``AgentUnavailableError`` names the problem)."""
    agent: PerceptionAgentBase = build_agent(ref, "perception")
    return agent
