"""The model-call cache against a real local OpenAI-compatible server through real LiteLLM.

A repeat is answered from the folder with no request and no cost; any change of the request misses;
failures are never stored; a damaged or foreign entry is a miss with a warning; hits are counted per step.
"""

from __future__ import annotations

import base64
import json
import logging
import os
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from tests.support.openai_server import OpenAIServer, reply, status
from workers.agents import EpisodeModels
from workers.contract import ModelCallError, ModelSpec, RetryPolicy, StepRecord
from workers.llm import CircuitBreaker, ModelCache, ModelClient, load_litellm, uncacheable

pytestmark = pytest.mark.usefixtures("litellm_clients")

KEY_ENV = "SCRATCHWORLD_TEST_CACHE_KEY"
SECRET = "sk-cache-test-5e1d9b7a3c"
FAST = RetryPolicy(max_attempts=2, initial_backoff_s=0.01, max_backoff_s=0.02, request_timeout_s=5, max_total_s=20)
PRICED = "openai/cache-priced-model"
SCREEN = bytes(range(256)) * 800  # 200 KiB of "image"
MESSAGES = [
    {"role": "system", "content": "You act in Scratch."},
    {
        "role": "user",
        "content": [
            {"type": "text", "text": "Add a block."},
            {"type": "image_url", "image_url": {"url": "data:image/png;base64," + base64.b64encode(SCREEN).decode()}},
        ],
    },
]


@pytest.fixture(autouse=True)
async def priced(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(KEY_ENV, SECRET)
    litellm = await load_litellm()
    prices = {"input_cost_per_token": 1e-6, "output_cost_per_token": 2e-6, "litellm_provider": "openai", "mode": "chat"}
    litellm.register_model({PRICED: prices})


@pytest.fixture
def server() -> Iterator[OpenAIServer]:
    with OpenAIServer(default=reply("from the model", prompt_tokens=1000, completion_tokens=50)) as running:
        yield running


@pytest.fixture
def cache(tmp_path: Path) -> ModelCache:
    return ModelCache(tmp_path / "model-cache")


def client(
    server: OpenAIServer, model: str = PRICED, breaker: CircuitBreaker | None = None, **fields: Any
) -> ModelClient:
    spec = ModelSpec(
        **{"name": "m", "model": model, "api_base": server.url, "api_key_env": KEY_ENV, "temperature": 0, **fields}
    )
    return ModelClient(spec, FAST, breaker=breaker or CircuitBreaker(f"cache-{model}", failures=1000))


def entries(cache: ModelCache) -> list[Path]:
    return sorted(cache.folder.glob("*/*.json")) if cache.folder.exists() else []


async def test_a_repeat_is_answered_from_the_cache_with_no_request_and_no_cost(
    server: OpenAIServer, cache: ModelCache
) -> None:
    model = client(server)
    first = await model.complete(MESSAGES, seed=7, cache=cache)
    again = await model.complete(MESSAGES, seed=7, cache=cache)

    assert server.count == 1
    assert (first.cached, first.cost_usd) == (False, pytest.approx(1000 * 1e-6 + 50 * 2e-6))
    assert again.cached and again.cost_usd == 0.0 and again.attempts == 0
    assert (again.text, again.input_tokens, again.output_tokens) == ("from the model", 1000, 50)
    (stored,) = entries(cache)
    entry = json.loads(stored.read_bytes())
    assert stored.name == f"{entry['key']}.json" and stored.parent.name == entry["key"][:2]
    assert (entry["model"], entry["seed"], entry["text"]) == (PRICED, 7, "from the model")
    assert SECRET.encode() not in stored.read_bytes()
    assert not [p for p in stored.parent.iterdir() if p.name.endswith(".tmp")]


async def test_another_run_naming_the_same_folder_replays(server: OpenAIServer, cache: ModelCache) -> None:
    await client(server).complete(MESSAGES, seed=1, cache=cache)
    other = ModelCache(Path(str(cache.folder)))  # another run (or node) naming the same folder
    replayed = await client(server).complete(MESSAGES, seed=1, cache=other)
    assert replayed.cached and server.count == 1


def _changed_image(messages: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """The same screenshot with its very last byte changed: the key must hash images in full."""
    screen = SCREEN[:-1] + bytes([SCREEN[-1] ^ 1])
    url = "data:image/png;base64," + base64.b64encode(screen).decode()
    return [
        messages[0],
        {**messages[1], "content": [messages[1]["content"][0], {"type": "image_url", "image_url": {"url": url}}]},
    ]


CHANGES: dict[str, tuple[dict[str, Any], Any, int]] = {
    # name: (ModelSpec fields changed, messages, seed)
    "system message": ({}, [{"role": "system", "content": "You act in Scratch!"}, MESSAGES[1]], 7),
    "image, last byte": ({}, _changed_image(MESSAGES), 7),
    "one more message": ({}, [*MESSAGES, {"role": "user", "content": "go"}], 7),
    "seed": ({}, MESSAGES, 8),
    "model": ({"model": "openai/cache-other-model"}, MESSAGES, 7),
    "temperature": ({"temperature": 0.5}, MESSAGES, 7),
    "max_tokens": ({"max_tokens": 100}, MESSAGES, 7),
    "params": ({"params": {"top_p": 0.9}}, MESSAGES, 7),
    "coordinates": ({"coordinates": "normalized_1000"}, MESSAGES, 7),
}


@pytest.mark.parametrize("change", list(CHANGES))
async def test_any_change_of_the_request_misses(server: OpenAIServer, cache: ModelCache, change: str) -> None:
    fields, messages, seed = CHANGES[change]
    await client(server).complete(MESSAGES, seed=7, cache=cache)
    server.push(reply("a fresh answer"))

    changed = await client(server, **fields).complete(messages, seed=seed, cache=cache)

    assert (changed.cached, changed.text, server.count) == (False, "a fresh answer", 2)
    assert len(entries(cache)) == 2
    assert (await client(server, **fields).complete(messages, seed=seed, cache=cache)).text == "a fresh answer"
    assert server.count == 2  # and the changed request is itself answered from the cache next time


async def test_the_endpoint_is_part_of_the_key(cache: ModelCache) -> None:
    with OpenAIServer() as one, OpenAIServer(default=reply("the other server")) as two:
        await client(one).complete(MESSAGES, seed=0, cache=cache)
        answer = await client(two).complete(MESSAGES, seed=0, cache=cache)
    assert (answer.cached, answer.text, one.count, two.count) == (False, "the other server", 1, 1)


@pytest.mark.parametrize(
    "failure",
    [
        [status(400)],
        [status(401)],
        [status(500), status(500)],
        [status(429, retry_after=0), status(429, retry_after=0)],
    ],
    ids=["bad-request", "auth", "server-error", "rate-limited"],
)
async def test_failed_calls_are_not_cached(server: OpenAIServer, cache: ModelCache, failure: list[Any]) -> None:
    server.push(*failure)
    with pytest.raises(ModelCallError):
        await client(server).complete(MESSAGES, seed=0, cache=cache)
    assert entries(cache) == []

    answer = await client(server).complete(MESSAGES, seed=0, cache=cache)
    assert (answer.cached, answer.text, server.count) == (False, "from the model", len(failure) + 1)
    assert len(entries(cache)) == 1


async def test_a_retried_call_stores_only_its_success(server: OpenAIServer, cache: ModelCache) -> None:
    server.push(status(500), reply("after a retry"))
    assert (await client(server).complete(MESSAGES, seed=0, cache=cache)).attempts == 2
    replayed = await client(server).complete(MESSAGES, seed=0, cache=cache)
    assert (replayed.cached, replayed.text, server.count) == (True, "after a retry", 2)


def _corrupt(path: Path, how: str, other: Path) -> None:
    if how == "torn":
        path.write_bytes(path.read_bytes()[:40])
    elif how == "not json":
        path.write_bytes(b"\x00\xffnot json at all")
    elif how == "wrong shape":
        entry = json.loads(path.read_bytes())
        path.write_text(json.dumps({**entry, "text": 5, "input_tokens": -1}))
    elif how == "extra field":
        entry = json.loads(path.read_bytes())
        path.write_text(json.dumps({**entry, "__class__": "os.system"}))
    elif how == "another request's entry":
        path.write_bytes(other.read_bytes())
    elif how == "other format":
        path.write_text(json.dumps({**json.loads(path.read_bytes()), "format": 99}))
    elif how == "symlink":
        path.unlink()
        path.symlink_to(other)
    elif how == "fifo":
        path.unlink()
        os.mkfifo(path)
    elif how == "directory":
        path.unlink()
        path.mkdir()
    elif how == "huge":
        path.write_bytes(b"{" + b" " * (9 * 1024 * 1024))
    else:
        raise AssertionError(how)


CORRUPTIONS = [
    "torn",
    "not json",
    "wrong shape",
    "extra field",
    "another request's entry",
    "other format",
    "symlink",
    "fifo",
    "directory",
    "huge",
]


@pytest.mark.parametrize("how", CORRUPTIONS)
async def test_a_damaged_or_foreign_entry_is_a_miss_with_a_warning(
    server: OpenAIServer, cache: ModelCache, how: str, caplog: pytest.LogCaptureFixture
) -> None:
    model = client(server)
    await model.complete([{"role": "user", "content": "another request"}], seed=0, cache=cache)
    (other,) = entries(cache)
    await model.complete(MESSAGES, seed=0, cache=cache)
    (target,) = set(entries(cache)) - {other}
    _corrupt(target, how, other)
    server.push(reply("asked again"))

    with caplog.at_level(logging.WARNING, logger="workers.llm"):
        answer = await model.complete(MESSAGES, seed=0, cache=cache)

    assert (answer.cached, answer.text, server.count) == (False, "asked again", 3)
    warnings = [
        r.getMessage() for r in caplog.records if r.name == "workers.llm._cache" and "calling" in r.getMessage()
    ]
    assert len(warnings) == 1 and str(target) in warnings[0] and "\n" not in warnings[0]
    if how != "directory":  # a fresh success takes the entry's place
        assert (await model.complete(MESSAGES, seed=0, cache=cache)).text == "asked again"
        assert server.count == 3


async def test_a_folder_that_cannot_take_entries_costs_a_warning_not_the_call(
    server: OpenAIServer, tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    blocked = tmp_path / "a-file"
    blocked.write_text("not a folder")
    with caplog.at_level(logging.WARNING, logger="workers.llm"):
        answer = await client(server).complete(MESSAGES, seed=0, cache=ModelCache(blocked / "cache"))
    assert answer.text == "from the model"
    assert any("cannot store" in r.getMessage() for r in caplog.records)


async def test_a_hit_is_answered_while_the_model_circuit_is_open(server: OpenAIServer, cache: ModelCache) -> None:
    breaker = CircuitBreaker("cache-open-circuit", failures=1, window_s=60, cooldown_s=600)
    model = client(server, breaker=breaker)
    await model.complete(MESSAGES, seed=0, cache=cache)
    server.push(status(500), status(500))
    with pytest.raises(ModelCallError):
        await model.complete([{"role": "user", "content": "fails"}], seed=0, cache=cache)
    with pytest.raises(ModelCallError) as refused:
        await model.complete([{"role": "user", "content": "fails again"}], seed=0, cache=cache)
    assert refused.value.error_class == "model_circuit_open"
    assert (await model.complete(MESSAGES, seed=0, cache=cache)).cached


def test_sampling_without_a_seed_is_not_cacheable() -> None:
    def spec(model: str, temperature: float | None = None, params: dict[str, Any] | None = None) -> ModelSpec:
        return ModelSpec(name="m", model=model, temperature=temperature, params=params or {})

    unseeded = "anthropic/claude-3-5-sonnet-20240620"  # LiteLLM sends Anthropic no seed
    assert uncacheable(spec(unseeded, 0)) is None
    assert uncacheable(spec(unseeded, None, {"temperature": 0})) is None
    assert uncacheable(spec("openai/gpt-4o", 0.7)) is None  # sampled, but under the episode's seed
    assert uncacheable(spec("openai/gpt-4o")) is None
    refused = uncacheable(spec(unseeded, 0.7))
    assert refused is not None and "temperature 0.7" in refused and unseeded in refused and "\n" not in refused
    unset = uncacheable(spec(unseeded))
    assert unset is not None and "temperature unset" in unset
    assert uncacheable(spec("openai/gpt-4o", 0.7), seeded=False) is not None  # a call made without a seed
    assert uncacheable(spec("openai/gpt-4o", 0), seeded=False) is None


async def test_an_uncacheable_model_is_called_every_time(
    server: OpenAIServer, cache: ModelCache, caplog: pytest.LogCaptureFixture
) -> None:
    """An agent's own ModelSpec escapes the config's check; the client refuses it too (warned once)."""
    model = client(server, model="deepinfra/cache-sampled", temperature=0.9)  # OpenAI-compatible, takes no seed
    assert uncacheable(model.spec) is not None
    with caplog.at_level(logging.WARNING, logger="workers.llm"):
        for _ in range(3):
            assert not (await model.complete(MESSAGES, seed=0, cache=cache)).cached
    assert (server.count, entries(cache)) == (3, [])
    assert "seed" not in server.requests[0].body
    assert len([r for r in caplog.records if "not caching" in r.getMessage()]) == 1


async def test_hits_are_counted_on_their_step(server: OpenAIServer, cache: ModelCache) -> None:
    spec = client(server).spec
    first_episode = EpisodeModels(FAST, seed=4, cache=cache)
    reply_one = await first_episode.connect(spec).complete(MESSAGES)
    calls = first_episode.drain()
    assert (calls.llm_calls, calls.cache_hits, reply_one.cached) == (1, 0, False)

    rerun = EpisodeModels(FAST, seed=4, cache=cache)
    handle = rerun.connect(spec)
    reply_two = await handle.complete(MESSAGES)
    await handle.complete(
        [*MESSAGES, {"role": "assistant", "content": reply_two.text}, {"role": "user", "content": "next"}]
    )
    step = rerun.drain().booked_on(StepRecord(index=0, action="done", ok=True))

    assert reply_two.cached and reply_two.cost_usd == 0.0
    assert (step.llm_calls, step.llm_cache_hits, server.count) == (2, 1, 2)
    assert step.cost_usd == pytest.approx(1000 * 1e-6 + 50 * 2e-6)  # only the new call cost money
    assert step.reply == "from the model"
