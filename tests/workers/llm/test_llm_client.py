"""ModelClient against a real local OpenAI-compatible server through real LiteLLM: retries, classes, cost, secrets."""

from __future__ import annotations

import logging
import time
import traceback
from collections.abc import Iterator

import pytest

from tests.support.openai_server import (
    OpenAIServer,
    context_length_error,
    drop,
    hang,
    malformed,
    reply,
    status,
)
from workers.contract import ModelCallError, ModelSpec, RetryPolicy
from workers.llm import CircuitBreaker, ModelClient, load_litellm
from workers.llm._client import _parse_retry_after

pytestmark = pytest.mark.usefixtures("litellm_clients")

KEY_ENV = "SCRATCHWORLD_TEST_LLM_KEY"
SECRET = "sk-test-7f3a9c1e5b2d4f60"
MESSAGES = [{"role": "system", "content": "You act in Scratch."}, {"role": "user", "content": "Add a block."}]
FAST = RetryPolicy(max_attempts=4, initial_backoff_s=0.01, max_backoff_s=0.05, request_timeout_s=5, max_total_s=20)


@pytest.fixture(autouse=True)
def api_key(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(KEY_ENV, SECRET)


@pytest.fixture
def server() -> Iterator[OpenAIServer]:
    with OpenAIServer() as running:
        yield running


def client(
    server: OpenAIServer,
    policy: RetryPolicy = FAST,
    model: str = "openai/test-model",
    breaker: CircuitBreaker | None = None,
    **fields: object,
) -> ModelClient:
    spec = ModelSpec(**{"name": "test", "model": model, "api_base": server.url, "api_key_env": KEY_ENV, **fields})  # type: ignore[arg-type]
    return ModelClient(spec, policy, breaker=breaker or CircuitBreaker(model, failures=1000))


async def failure(model_client: ModelClient, seed: int | None = None) -> ModelCallError:
    with pytest.raises(ModelCallError) as caught:
        await model_client.complete(MESSAGES, seed)
    return caught.value


async def test_success_reports_text_usage_and_exact_cost(server: OpenAIServer) -> None:
    litellm = await load_litellm()
    prices = {"input_cost_per_token": 1e-6, "output_cost_per_token": 2e-6, "litellm_provider": "openai", "mode": "chat"}
    litellm.register_model({"openai/priced-model": prices})
    server.push(reply("Analysis: fine.", prompt_tokens=1000, completion_tokens=500))

    completion = await client(server, model="openai/priced-model").complete(MESSAGES)

    assert completion.text == "Analysis: fine."
    assert (completion.input_tokens, completion.output_tokens) == (1000, 500)
    assert completion.cost_usd == pytest.approx(1000 * 1e-6 + 500 * 2e-6, abs=1e-12)
    assert completion.attempts == 1
    assert completion.model == "priced-model"
    assert completion.finish_reason == "stop"
    assert 0 < completion.latency_s <= completion.total_s
    assert server.requests[0].body["messages"] == MESSAGES


async def test_unknown_model_costs_nothing_and_warns_once(
    server: OpenAIServer, caplog: pytest.LogCaptureFixture
) -> None:
    model_client = client(server, model="openai/unpriced-model-x17")
    with caplog.at_level(logging.WARNING, logger="workers.llm"):
        first = await model_client.complete(MESSAGES)
        second = await model_client.complete(MESSAGES)
    assert first.cost_usd == second.cost_usd == 0.0
    warnings = [r for r in caplog.records if r.name.startswith("workers.llm") and "unpriced-model-x17" in r.message]
    assert len(warnings) == 1


async def test_rate_limit_honours_retry_after(server: OpenAIServer) -> None:
    server.push(status(429, retry_after=1), reply("ok"))
    completion = await client(server).complete(MESSAGES)
    first, second = server.requests
    assert completion.attempts == 2
    assert second.time - first.time >= 0.95


async def test_server_errors_are_retried_until_success(server: OpenAIServer) -> None:
    server.push(status(500), status(500), reply("third time"))
    completion = await client(server).complete(MESSAGES)
    assert completion.text == "third time"
    assert completion.attempts == server.count == 3


async def test_persistent_server_error_stops_after_max_attempts(server: OpenAIServer) -> None:
    server.default = status(500)
    error = await failure(client(server))
    assert (error.error_class, error.transient, error.attempts, error.status_code) == (
        "model_provider_error",
        True,
        4,
        500,
    )
    assert server.count == 4


@pytest.mark.parametrize(
    ("behaviour", "error_class"),
    [
        (status(401), "model_auth"),
        (status(403), "model_auth"),
        (status(400), "model_bad_request"),
        (status(404), "model_not_found"),
        (context_length_error(), "model_context_window"),
    ],
)
async def test_permanent_errors_are_not_retried(server: OpenAIServer, behaviour: object, error_class: str) -> None:
    server.default = behaviour  # type: ignore[assignment]
    error = await failure(client(server))
    assert (error.error_class, error.transient, error.attempts) == (error_class, False, 1)
    assert server.count == 1


async def test_hang_past_request_timeout_is_a_timeout(server: OpenAIServer) -> None:
    server.default = hang(120)  # replies only after 2 minutes: an error before that is the request timeout's
    policy = FAST.model_copy(update={"request_timeout_s": 1.0, "max_attempts": 1})
    started = time.monotonic()
    error = await failure(client(server, policy))
    assert (error.error_class, error.transient, error.attempts, server.count) == ("model_timeout", True, 1, 1)
    assert time.monotonic() - started >= 0.9  # not before the timeout (a lower bound: load only lengthens it)


async def test_timeout_is_retried(server: OpenAIServer) -> None:
    server.push(hang(5), reply("after the hang"))
    policy = FAST.model_copy(update={"request_timeout_s": 0.5})
    completion = await client(server, policy).complete(MESSAGES)
    assert (completion.text, completion.attempts) == ("after the hang", 2)


@pytest.mark.parametrize(
    ("behaviour", "error_class"), [(drop(), "model_connection"), (malformed(), "model_provider_error")]
)
async def test_dropped_and_malformed_answers_are_retried_then_classified(
    server: OpenAIServer, behaviour: object, error_class: str
) -> None:
    server.push(behaviour)  # type: ignore[arg-type]
    assert (await client(server).complete(MESSAGES)).attempts == 2

    server.default = behaviour  # type: ignore[assignment]
    error = await failure(client(server))
    assert (error.error_class, error.transient, error.attempts) == (error_class, True, 4)


async def test_refused_connection_is_a_connection_error() -> None:
    with OpenAIServer() as gone:
        url = gone.url
    spec = ModelSpec(name="test", model="openai/test-model", api_base=url, api_key_env=KEY_ENV)
    policy = FAST.model_copy(update={"max_attempts": 2})
    error = await failure(ModelClient(spec, policy, breaker=CircuitBreaker("refused")))
    assert (error.error_class, error.attempts) == ("model_connection", 2)


async def test_max_total_bounds_the_whole_call(server: OpenAIServer) -> None:
    server.default = status(500)
    policy = RetryPolicy(max_attempts=100, initial_backoff_s=0.3, max_backoff_s=0.3, max_total_s=1.5)
    started = time.monotonic()
    error = await failure(client(server, policy))
    # Only the total budget can stop it short of max_attempts (those would take ~15 s of back-off);
    # retries went on until the budget was spent (a lower bound: load only lengthens the call).
    assert 1 < error.attempts < 100 and error.attempts == server.count
    assert time.monotonic() - started >= 1.5 - 0.3  # the last back-off (at most 0.3 s) would have crossed it


async def test_retry_after_beyond_the_total_budget_fails_at_once(
    server: OpenAIServer, caplog: pytest.LogCaptureFixture
) -> None:
    server.default = status(429, retry_after=30)
    policy = FAST.model_copy(update={"max_total_s": 5.0})
    with caplog.at_level(logging.INFO, logger="workers.llm"):
        error = await failure(client(server, policy))
    assert (error.error_class, error.attempts, server.count) == ("model_rate_limited", 1, 1)
    # No back-off was scheduled: a retry is logged ("retrying in 30.00 s") before its sleep starts.
    assert "retrying in" not in caplog.text


async def test_circuit_breaker_opens_fails_fast_and_recovers(server: OpenAIServer) -> None:
    server.default = status(503)
    now = [1000.0]  # the breaker's clock, moved by the test: the cool-down passes when the test says so
    breaker = CircuitBreaker("flaky", failures=2, window_s=60, cooldown_s=30, clock=lambda: now[0])
    model_client = client(server, FAST.model_copy(update={"max_attempts": 2}), breaker=breaker)
    for _ in range(2):
        assert (await failure(model_client)).error_class == "model_provider_error"
    assert (server.count, breaker.state) == (4, "open")

    error = await failure(model_client)
    assert (error.error_class, error.attempts, error.transient) == ("model_circuit_open", 0, True)
    assert server.count == 4  # failed fast: no request

    now[0] += 29.9
    assert breaker.state == "open"
    assert (await failure(model_client)).error_class == "model_circuit_open" and server.count == 4
    now[0] += 0.1
    assert breaker.state == "half_open"
    server.push(reply("back"))
    assert (await model_client.complete(MESSAGES)).text == "back"
    assert breaker.state == "closed"


async def test_bad_requests_do_not_open_the_circuit(server: OpenAIServer) -> None:
    server.default = status(400)
    breaker = CircuitBreaker("bad", failures=1, window_s=60, cooldown_s=60)
    await failure(client(server, breaker=breaker))
    assert breaker.state == "closed"


async def test_api_key_reaches_the_server_but_no_log_or_error(
    server: OpenAIServer, caplog: pytest.LogCaptureFixture
) -> None:
    echo = {"error": {"message": f"Incorrect API key provided: {SECRET}.", "type": "invalid_request_error"}}
    server.push(status(500), reply("ok"), status(401, body=echo))
    model_client = client(server)
    with caplog.at_level(logging.DEBUG):
        await model_client.complete(MESSAGES)
        error = await failure(model_client)

    assert {r.headers["authorization"] for r in server.requests} == {f"Bearer {SECRET}"}
    assert error.error_class == "model_auth"
    assert "Incorrect API key provided" in str(error)
    rendered = "".join(traceback.format_exception(error))
    assert SECRET not in rendered
    assert SECRET not in caplog.text
    assert all(SECRET not in repr(record.args) for record in caplog.records)


async def test_missing_key_variable_fails_without_a_request(
    server: OpenAIServer, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.delenv(KEY_ENV)
    error = await failure(client(server))
    assert (error.error_class, error.attempts, server.count) == ("model_auth", 0, 0)
    assert KEY_ENV in str(error)


async def test_no_credentials_at_all_is_auth_and_not_retried(
    server: OpenAIServer, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.delenv("OPENAI_API_KEY", raising=False)
    spec = ModelSpec(name="test", model="openai/test-model", api_base=server.url)  # no api_key_env either
    error = await failure(ModelClient(spec, FAST, breaker=CircuitBreaker("no-key", failures=1000)))
    assert (error.error_class, error.transient, error.attempts, server.count) == ("model_auth", False, 1, 0)


async def test_base_url_from_the_environment(server: OpenAIServer, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("SCRATCHWORLD_TEST_BASE_URL", server.url)
    await client(server, api_base=None, api_base_env="SCRATCHWORLD_TEST_BASE_URL").complete(MESSAGES)
    assert server.count == 1
    monkeypatch.delenv("SCRATCHWORLD_TEST_BASE_URL")
    error = await failure(client(server, api_base=None, api_base_env="SCRATCHWORLD_TEST_BASE_URL"))
    assert (error.error_class, error.attempts, server.count) == ("model_bad_request", 0, 1)
    assert "SCRATCHWORLD_TEST_BASE_URL" in str(error)


async def test_seed_and_sampling_parameters_are_forwarded(server: OpenAIServer) -> None:
    model_client = client(server, temperature=0.0, max_tokens=256, params={"top_p": 0.5})
    await model_client.complete(MESSAGES, seed=7)
    await model_client.complete(MESSAGES)
    with_seed, without_seed = (request.body for request in server.requests)
    assert (with_seed["seed"], with_seed["temperature"], with_seed["max_tokens"], with_seed["top_p"]) == (
        7,
        0.0,
        256,
        0.5,
    )
    assert "seed" not in without_seed


def test_retry_after_header_forms() -> None:
    assert _parse_retry_after(None, "2") == 2.0
    assert _parse_retry_after("1500", "9") == 1.5
    assert _parse_retry_after(None, "Wed, 21 Oct 2015 07:28:00 GMT") == 0.0  # a date in the past
    future = time.strftime("%a, %d %b %Y %H:%M:%S GMT", time.gmtime(time.time() + 30))
    assert 25 < (_parse_retry_after(None, future) or 0) <= 30
    assert _parse_retry_after(None, "soon") is None
