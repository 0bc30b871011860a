"""What an episode's model calls leave in its steps: each new message once, replies, tokens, images by hash.

Real LiteLLM calls against the local OpenAI-compatible test server; no browser.
"""

from __future__ import annotations

import base64
import hashlib
from collections.abc import Iterator
from typing import Any

import pytest

from tests.support.openai_server import OpenAIServer, reply, status
from workers.agents import EpisodeModels
from workers.contract import ModelCallError, ModelSpec, RetryPolicy

FAST = RetryPolicy(max_attempts=3, initial_backoff_s=0.01, max_backoff_s=0.02, request_timeout_s=10, max_total_s=30)
KEY_ENV = "SCRATCHWORLD_TEST_CALLS_KEY"
pytestmark = pytest.mark.usefixtures("litellm_clients")


@pytest.fixture
def server(monkeypatch: pytest.MonkeyPatch) -> Iterator[OpenAIServer]:
    monkeypatch.setenv(KEY_ENV, "sk-calls")
    with OpenAIServer() as running:
        yield running


def model(server: OpenAIServer, name: str = "openai/gpt-4o-mini") -> ModelSpec:
    return ModelSpec(name="m", model=name, api_base=server.url, api_key_env=KEY_ENV)


def user(text: str, png: bytes | None = None) -> dict[str, Any]:
    if png is None:
        return {"role": "user", "content": text}
    url = "data:image/png;base64," + base64.b64encode(png).decode()
    return {
        "role": "user",
        "content": [{"type": "text", "text": text}, {"type": "image_url", "image_url": {"url": url}}],
    }


async def test_a_sliding_conversation_records_each_new_message_once(server: OpenAIServer) -> None:
    server.push(*(reply(f"answer {n}", prompt_tokens=100, completion_tokens=7) for n in range(4)))
    models = EpisodeModels(FAST, seed=3)
    handle = models.connect(model(server))
    system = {"role": "system", "content": "rules"}
    history: list[dict[str, Any]] = []
    prompts = []
    for turn in range(4):
        history.append(user("same observation"))  # a stuck agent sees the same text every turn
        window = history[-3:]
        while window[0]["role"] != "user":
            window = window[1:]
        answer = await handle.complete([system, *window])
        history.append({"role": "assistant", "content": answer.text})
        step = models.drain()
        prompts.append(step.prompt)
        assert (step.llm_calls, step.input_tokens, step.output_tokens, step.reply) == (1, 100, 7, f"answer {turn}")
        assert step.cost_usd > 0
    assert prompts[0] == [system, user("same observation")]
    assert prompts[1:] == [[user("same observation")]] * 3  # each turn's message, though its text repeats
    assert server.requests[0].body["seed"] == 3


async def test_images_are_kept_once_by_hash_and_two_conversations_are_told_apart(server: OpenAIServer) -> None:
    server.push(reply("plan"), reply("point"))
    models = EpisodeModels(FAST, seed=0)
    planner, grounder = models.connect(model(server)), models.connect(model(server, "openai/gpt-4o"))
    png = b"\x89PNG-screen"
    await planner.complete([{"role": "system", "content": "plan"}, user("what next?", png)])
    await grounder.complete([{"role": "system", "content": "ground"}, user("where is the cat?", png)])
    step = models.drain()
    digest = hashlib.sha256(png).hexdigest()
    assert models.images == {digest: png}
    assert step.llm_calls == 2 and step.reply == "point"
    roles = [m["role"] for m in step.prompt]  # type: ignore[index]
    assert roles == ["system", "user", "assistant", "system", "user"]  # the first call's reply kept in order
    refs = [p for m in step.prompt for p in m["content"] if isinstance(p, dict) and p.get("type") == "image_ref"]  # type: ignore[index,union-attr]
    assert refs == [{"type": "image_ref", "sha256": digest}] * 2


async def test_failed_calls_raise_classified_and_retries_are_not_counted_as_calls(server: OpenAIServer) -> None:
    server.push(status(500), reply("fine"), status(401))
    models = EpisodeModels(FAST, seed=0)
    handle = models.connect(model(server))
    assert (await handle.complete([user("hi")])).text == "fine"
    with pytest.raises(ModelCallError) as failed:
        await handle.complete([user("again")])
    assert failed.value.error_class == "model_auth"
    step = models.drain()
    assert (step.llm_calls, server.count) == (1, 3)
