"""The ``llm`` agent: a model behind LiteLLM reads each observation and answers with one action.

One conversation per episode: the system prompt of the mode, then per turn a user message (the
previous action's result, the observation; in primitive mode the screenshot as an image part)
and the model's reply. Only the newest ``history_messages`` messages are sent, and by default
only the newest screenshot. A reply without a usable action costs the step and its parse error
is shown to the model next turn; a model call that fails for good raises ``ModelCallError``,
which ends the job as an error of that class.

What each step sent and received is recorded on its ``StepRecord`` (images by hash, each image
kept once in ``images``) so a trajectory can be read back turn by turn.
"""

from __future__ import annotations

import base64
import hashlib
import sys
from dataclasses import dataclass
from typing import Any

from pydantic import JsonValue

from workers.agents._coordinates import coordinate_system, to_page
from workers.agents._prompts import result_text, system_prompt
from workers.contract import (
    Action,
    CompositeObservation,
    EpisodeSpec,
    InvalidReply,
    LLMSettings,
    ModelSpec,
    PrimitiveObservation,
    RetryPolicy,
    StepRecord,
    TaskPayload,
    composite_action,
    primitive_action,
)
from workers.llm import (
    Completion,
    LocalLimiterHandle,
    ModelClient,
    RateLimiterHandle,
    RayLimiterHandle,
    ReplyParseError,
    model_key,
    parse_reply,
)

_clients: dict[tuple[str, RetryPolicy], ModelClient] = {}
_local_limiters: dict[str, LocalLimiterHandle] = {}


def shared_client(model: ModelSpec, policy: RetryPolicy) -> ModelClient:
    """One client per model key and policy in this process, so episodes share its breaker and limiter."""
    key = (model_key(model), policy)
    if key not in _clients:
        _clients[key] = ModelClient(model, policy, _limiter(model))
    return _clients[key]


def _limiter(model: ModelSpec) -> RateLimiterHandle | None:
    """The cluster's limiter under Ray (the driver created it), else one per process."""
    if model.rate_limits is None:
        return None
    key = model_key(model)
    ray = sys.modules.get("ray")
    if ray is not None and ray.is_initialized():
        return RayLimiterHandle(key, model.rate_limits)
    if key not in _local_limiters:
        _local_limiters[key] = LocalLimiterHandle(model.rate_limits)
    return _local_limiters[key]


class LLMAgent:
    """Asks a model for every action of one episode."""

    observes = True

    def __init__(self, spec: EpisodeSpec, task: TaskPayload, client: ModelClient | None = None) -> None:
        if spec.model is None:
            raise ValueError("the llm agent needs a model")
        self.mode = spec.mode
        self.seed = spec.seed
        self.settings = spec.llm or LLMSettings()
        self.coordinates = coordinate_system(spec.model)
        self.instruction = task.instruction
        self.client = client or shared_client(spec.model, self.settings.retry)
        self.images: dict[str, bytes] = {}
        """Screenshots sent to the model, by SHA-256."""

        self._system: dict[str, Any] | None = None
        self._history: list[dict[str, Any]] = []
        self._feedback: str | None = None
        self._system_recorded = False
        self._turn: _Turn | None = None

    async def brief(self, block_catalog: str | None) -> None:
        """Write the system prompt; composite mode lists the editor's blocks."""
        text = system_prompt(
            self.mode,
            self.instruction,
            block_catalog=block_catalog,
            coordinates=self.coordinates,
            element_list=self.settings.element_list,
        )
        self._system = {"role": "system", "content": text}

    async def act(self, observation: CompositeObservation | PrimitiveObservation | None) -> Action:
        if self._system is None:
            await self.brief(None)
        assert self._system is not None
        user, recorded = self._user_message(observation)
        prompt = [recorded] if self._system_recorded else [self._system, recorded]
        self._system_recorded = True
        if self.settings.last_screenshot_only:  # older turns keep their text only (and memory stays flat)
            self._history = [_without_images(message) for message in self._history]
        self._history.append(user)
        completion = await self.client.complete(self._messages(), seed=self.seed)
        self._history.append({"role": "assistant", "content": completion.text})
        self._turn = _Turn(prompt=prompt, completion=completion)
        try:
            parsed = parse_reply(completion.text)
        except ReplyParseError as error:
            return InvalidReply(reason=error.reason, message=str(error))
        request: dict[str, JsonValue] = {"api": parsed.api, "args": parsed.args}
        if self.mode == "composite":
            return composite_action(request)
        return primitive_action({"api": parsed.api, "args": to_page(parsed.args, self.coordinates)})

    def after_step(self, step: StepRecord) -> StepRecord:
        """Remember what the action did (shown next turn) and put the turn's prompt and cost on the step."""
        if self.settings.show_action_result:
            self._feedback = result_text(step.ok, step.data, step.error_code, step.error_message)
        turn, self._turn = self._turn, None
        if turn is None:
            return step
        completion = turn.completion
        update = {
            "llm_calls": 1,
            "input_tokens": completion.input_tokens,
            "output_tokens": completion.output_tokens,
            "cost_usd": completion.cost_usd,
            "prompt": turn.prompt,
            "reply": completion.text,
        }
        return step.model_copy(update=update)

    def _user_message(
        self, observation: CompositeObservation | PrimitiveObservation | None
    ) -> tuple[dict[str, Any], dict[str, Any]]:
        """The message sent, and the same message as recorded (images by reference)."""
        texts = [self._feedback] if self._feedback else []
        self._feedback = None
        if isinstance(observation, PrimitiveObservation):
            if self.settings.element_list:
                texts.append(f"Element list:\n{observation.text}")
            if observation.warnings:
                texts.append("Note: " + "; ".join(observation.warnings))
            digest = hashlib.sha256(observation.screenshot_png).hexdigest()
            self.images.setdefault(digest, observation.screenshot_png)
            text = {"type": "text", "text": "\n\n".join(texts) or "Screenshot:"}
            url = "data:image/png;base64," + base64.b64encode(observation.screenshot_png).decode()
            sent = {"role": "user", "content": [text, {"type": "image_url", "image_url": {"url": url}}]}
            recorded = {"role": "user", "content": [text, {"type": "image_ref", "sha256": digest}]}
            return sent, recorded
        if observation is not None:
            texts.append(observation.text)
        message = {"role": "user", "content": "\n\n".join(texts)}
        return message, message

    def _messages(self) -> list[dict[str, Any]]:
        """System prompt plus the newest messages."""
        assert self._system is not None
        window = self._history[-self.settings.history_messages :]
        while window and window[0]["role"] != "user":  # providers want a user message first
            window = window[1:]
        return [self._system, *window]


@dataclass(frozen=True)
class _Turn:
    prompt: list[JsonValue]
    completion: Completion


def _without_images(message: dict[str, Any]) -> dict[str, Any]:
    content = message["content"]
    if not isinstance(content, list):
        return message
    kept = [part for part in content if part.get("type") != "image_url"]
    return {**message, "content": kept}
