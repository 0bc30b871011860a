"""The ``llm`` agent: a model behind LiteLLM reads each observation and answers with one action.

One conversation per episode: the system prompt of the mode, then per turn a user message (the
previous action's result, the observation; in primitive mode the screenshot as an image part)
and the model's reply. Only the newest ``history_messages`` messages are sent, and by default
only the newest screenshot. A reply without a usable action costs the step and its parse error
is shown to the model next turn; a model call that fails for good raises ``ModelCallError``,
which ends the job as an error of that class.

It is an agent of the public API like any plugin: its model calls go through
``context.model()``, which records what each step sent and received.
"""

from __future__ import annotations

import base64
from typing import Any, ClassVar

from pydantic import JsonValue

from workers.agent_api import AgentBase, ModelHandle, StepResult, TaskContext
from workers.agents._coordinates import coordinate_system, to_page
from workers.agents._prompts import result_text, system_prompt
from workers.contract import (
    Action,
    CompositeObservation,
    InvalidReply,
    LLMSettings,
    Mode,
    Observation,
    PrimitiveObservation,
    composite_action,
    primitive_action,
)
from workers.llm import ReplyParseError, parse_reply


class LLMAgent(AgentBase):
    """Asks a model for every action of one episode."""

    needs_model: ClassVar[bool] = True

    async def start(self, context: TaskContext) -> None:
        self.mode: Mode = context.mode
        self.settings: LLMSettings = context.llm
        self.model: ModelHandle = context.model()
        self.coordinates = coordinate_system(self.model.spec)
        self._system: dict[str, Any] = {"role": "system", "content": await self.system_text(context)}
        self._history: list[dict[str, Any]] = []

    async def system_text(self, context: TaskContext, workflows: str = "") -> str:
        """The episode's system prompt (subclasses add to it, e.g. a memory of workflows)."""
        return system_prompt(
            self.mode,
            context.instruction,
            block_catalog=await context.block_catalog(),
            coordinates=self.coordinates,
            element_list=self.settings.element_list,
            workflows=workflows,
        )

    async def act(self, observation: Observation | None, last: StepResult | None) -> Action:
        feedback = None
        if last is not None and self.settings.show_action_result:
            feedback = result_text(last.ok, last.data, last.error_code, last.error_message)
        if self.settings.last_screenshot_only:  # older turns keep their text only (and memory stays flat)
            self._history = [_without_images(message) for message in self._history]
        self._history.append(self._user_message(observation, feedback))
        reply = await self.model.complete(self._messages())
        self._history.append({"role": "assistant", "content": reply.text})
        try:
            parsed = parse_reply(reply.text)
        except ReplyParseError as error:
            return InvalidReply(reason=error.reason, message=str(error))
        return await self.to_action(parsed.api, parsed.args, observation)

    async def to_action(self, api: str, args: dict[str, JsonValue], observation: Observation | None) -> Action:
        """The action a parsed reply asks for (primitive positions mapped from the model's convention)."""
        if self.mode == "composite":
            return composite_action({"api": api, "args": args})
        return primitive_action({"api": api, "args": to_page(args, self.coordinates)})

    def _user_message(self, observation: Observation | None, feedback: str | None) -> dict[str, Any]:
        texts = [feedback] if feedback else []
        if isinstance(observation, PrimitiveObservation):
            if self.settings.element_list:
                texts.append(f"Element list:\n{observation.text}")
            if observation.warnings:
                texts.append("Note: " + "; ".join(observation.warnings))
            text = {"type": "text", "text": "\n\n".join(texts) or "Screenshot:"}
            url = "data:image/png;base64," + base64.b64encode(observation.screenshot_png).decode()
            return {"role": "user", "content": [text, {"type": "image_url", "image_url": {"url": url}}]}
        if isinstance(observation, CompositeObservation):
            texts.append(observation.text)
        return {"role": "user", "content": "\n\n".join(texts)}

    def _messages(self) -> list[dict[str, Any]]:
        """System prompt plus the newest messages."""
        window = self._history[-self.settings.history_messages :]
        while window and window[0]["role"] != "user":  # providers want a user message first
            window = window[1:]
        return [self._system, *window]


def _without_images(message: dict[str, Any]) -> dict[str, Any]:
    content = message["content"]
    if not isinstance(content, list):
        return message
    kept = [part for part in content if part.get("type") != "image_url"]
    return {**message, "content": kept}
