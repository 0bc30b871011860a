"""The model calls of one episode: the handles an agent calls through, and what each step records.

Every agent, built-in or plugin, reaches models only through ``EpisodeModels.connect``: one
``ModelClient`` per model key and retry policy in this process (so episodes share its circuit
breaker and the cluster's rate limiter), and every call is written down for the step it was
made in: tokens, cost, the reply, and the messages that call added to what was already
recorded (a conversation's system prompt once, then each new turn), with images by SHA-256.
With the sweep's model cache, calls answered from it are counted as hits of their step.
"""

from __future__ import annotations

import base64
import binascii
import hashlib
import json
import sys
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from pydantic import JsonValue

from workers.agent_api import ModelHandle, ModelReply
from workers.contract import ModelSpec, RetryPolicy, StepRecord
from workers.llm import LocalLimiterHandle, ModelCache, ModelClient, RateLimiterHandle, RayLimiterHandle, model_key

_clients: dict[tuple[str, RetryPolicy], ModelClient] = {}
_local_limiters: dict[str, LocalLimiterHandle] = {}

_DATA_URL_PREFIX = "data:image/"


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


@dataclass
class StepCalls:
    """What the model calls made during one step add to its ``StepRecord``."""

    llm_calls: int = 0
    cache_hits: int = 0
    input_tokens: int = 0
    output_tokens: int = 0
    cost_usd: float = 0.0
    prompt: list[JsonValue] = field(default_factory=list)
    reply: str | None = None
    reasoning: str | None = None

    def booked_on(self, step: StepRecord) -> StepRecord:
        """``step`` with these calls added: counts summed, and the messages continuing its record (its
        own reply first, as the conversation saw it), the newest reply becoming the step's."""
        if not self.llm_calls:
            return step
        earlier_reply: list[JsonValue] = [{"role": "assistant", "content": step.reply}] if step.reply else []
        return step.model_copy(
            update={
                "llm_calls": step.llm_calls + self.llm_calls,
                "llm_cache_hits": step.llm_cache_hits + self.cache_hits,
                "input_tokens": step.input_tokens + self.input_tokens,
                "output_tokens": step.output_tokens + self.output_tokens,
                "cost_usd": step.cost_usd + self.cost_usd,
                "prompt": [*step.prompt, *earlier_reply, *self.prompt],
                "reply": self.reply,
                "reasoning": self.reasoning,
            }
        )


class EpisodeModels:
    """Connects an episode's agent to models, and keeps the record of its calls."""

    def __init__(
        self, policy: RetryPolicy, seed: int, client: ModelClient | None = None, cache: ModelCache | None = None
    ) -> None:
        """``cache``: the sweep's model cache (None: every call goes to the model)."""
        self.policy = policy
        self.seed = seed
        self.cache = cache
        self.images: dict[str, bytes] = {}
        """Images the prompts showed, by SHA-256 (kept once with the episode's result)."""

        self._client = client
        self._conversations: dict[str, list[str]] = {}
        """Per conversation (its first message), the keys of the last call's messages and its reply."""
        self._step = StepCalls()
        self.before_call: Callable[[], None] | None = None
        """Called as each model call begins (the episode runner gives back its start turn, so no one waits on a model,
        and has the page, which waits from now on, drop its start garbage)."""

    def connect(self, spec: ModelSpec) -> ModelHandle:
        return _Handle(self, spec, self._client or shared_client(spec, self.policy))

    async def call(self, client: ModelClient, messages: list[dict[str, Any]]) -> ModelReply:
        if self.before_call is not None:
            self.before_call()
        completion = await client.complete(messages, seed=self.seed, cache=self.cache)
        added = [self._recorded_form(message) for message in self._new_messages(messages, completion.text)]
        if self._step.reply is not None:  # an earlier call of this step: its reply joins the record
            self._step.prompt.append({"role": "assistant", "content": self._step.reply})
        self._step.prompt.extend(added)
        self._step.reply = completion.text
        self._step.reasoning = completion.reasoning
        self._step.llm_calls += 1
        self._step.cache_hits += int(completion.cached)
        self._step.input_tokens += completion.input_tokens
        self._step.output_tokens += completion.output_tokens
        self._step.cost_usd += completion.cost_usd
        return ModelReply(
            text=completion.text,
            input_tokens=completion.input_tokens,
            output_tokens=completion.output_tokens,
            cost_usd=completion.cost_usd,
            latency_s=completion.latency_s,
            cached=completion.cached,
        )

    def drain(self) -> StepCalls:
        """The calls since the last drain (one step's worth)."""
        step, self._step = self._step, StepCalls()
        return step

    def _new_messages(self, messages: list[dict[str, Any]], reply: str) -> list[dict[str, Any]]:
        """The messages this call adds to its conversation: what follows the longest run of its
        messages that ends the previous call's (a sliding history window drops from the front)."""
        keys = [_key(message) for message in messages]
        if not keys:
            return []
        before = self._conversations.get(keys[0])
        self._conversations[keys[0]] = [*keys, _key({"role": "assistant", "content": reply})]
        if before is None:
            return messages
        body, earlier = keys[1:], before[1:]
        kept = next(
            (n for n in range(min(len(body), len(earlier)), 0, -1) if body[:n] == earlier[-n:]),
            0,
        )
        return messages[1 + kept :]

    def _recorded_form(self, message: dict[str, Any]) -> JsonValue:
        """The message as the trajectory keeps it: data-URL images become references to ``images``."""
        content = message.get("content")
        if not isinstance(content, list):
            return json.loads(json.dumps(message, default=str))
        parts: list[JsonValue] = []
        for part in content:
            url = part.get("image_url", {}).get("url", "") if isinstance(part, dict) else ""
            image = _decoded(url) if part.get("type") == "image_url" else None
            if image is None:
                parts.append(json.loads(json.dumps(part, default=str)))
                continue
            digest = hashlib.sha256(image).hexdigest()
            self.images.setdefault(digest, image)
            parts.append({"type": "image_ref", "sha256": digest})
        return {
            **json.loads(json.dumps({k: v for k, v in message.items() if k != "content"}, default=str)),
            "content": parts,
        }


@dataclass
class _Handle:
    models: EpisodeModels
    spec: ModelSpec
    client: ModelClient

    async def complete(self, messages: list[dict[str, Any]]) -> ModelReply:
        return await self.models.call(self.client, messages)


def _key(message: dict[str, Any]) -> str:
    """A message's identity for the record: its role and text (a message whose image was later dropped
    from the history, as the llm agent does for older turns, is the same message)."""
    content = message.get("content")
    if isinstance(content, list):
        content = [part.get("text") for part in content if isinstance(part, dict) and part.get("type") == "text"]
    return hashlib.sha256(json.dumps([message.get("role"), content], default=str).encode()).hexdigest()


def _decoded(url: str) -> bytes | None:
    if not url.startswith(_DATA_URL_PREFIX) or ";base64," not in url:
        return None
    try:
        return base64.b64decode(url.split(";base64,", 1)[1], validate=True)
    except (binascii.Error, ValueError):
        return None
