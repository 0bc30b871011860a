"""The preflight refuses a sweep with a broken model before any job starts, one line per model.

A real local OpenAI-compatible server answers the probes (404 for an unknown model, 401 for a refused key,
scripted 5xx/429/400 for the retry and fallback cases) and real LiteLLM makes them; the sweeps are of the
perception benchmark (no browser). A sweep whose probe is refused has started its private Ray meanwhile (and
its workers: ``test_preflight_beside_workers.py``) and shuts it down; one whose settings are wrong stops before
that.
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import ray
import yaml

from scratchworld_dist._run import plan_run
from scratchworld_dist.scheduling import ModelCalls, run_preflight
from scratchworld_dist.sweep import load_sweep_config
from tests.conftest import SUITE_DIR
from tests.support.cli_runner import invoke
from tests.support.closed_port import closed_port
from tests.support.openai_server import Behaviour, OpenAIServer, reply, status
from tests.support.perception_suites import write_suite
from workers.contract import ModelSpec, RetryPolicy
from workers.llm import PROBE_MESSAGES, check_models

BASE_ENV, KEY_ENV, UNSET_ENV = "PREFLIGHT_TEST_BASE_URL", "PREFLIGHT_TEST_API_KEY", "PREFLIGHT_TEST_UNSET_KEY"
KEY = "sk-preflight-7d41c9e2"
FAST = {"max_attempts": 2, "initial_backoff_s": 0.05, "max_backoff_s": 0.1}


def answer(body: dict[str, Any]) -> Behaviour:
    """``missing`` is no model of this server, ``denied`` a model the key may not use; the rest answer."""
    if body.get("model") == "missing":
        return status(404)
    if body.get("model") == "denied":
        return status(401)
    return reply("OK", prompt_tokens=14, completion_tokens=1)


@pytest.fixture(scope="module")
def module_server() -> Iterator[OpenAIServer]:
    with OpenAIServer(responder=answer) as running, pytest.MonkeyPatch.context() as env:
        env.setenv(BASE_ENV, running.url)
        env.setenv(KEY_ENV, KEY)
        env.delenv(UNSET_ENV, raising=False)
        env.delenv("RAY_ADDRESS", raising=False)
        yield running


@pytest.fixture
def server(module_server: OpenAIServer) -> OpenAIServer:
    return module_server.reset(answer)


def model(name: str, model: str = "openai/gpt-4o-mini", **fields: Any) -> dict[str, Any]:
    found = {"model": model, "name": name, "api_base_env": BASE_ENV, "api_key_env": KEY_ENV}
    found.update(fields)
    return {k: v for k, v in found.items() if v is not None}


GOOD = model("good")
CLOSED_BASE = "http://127.0.0.1:{closed_port}/v1"  # the port is held closed for the test's length


def perception_sweep(tmp_path: Path, models: list[dict[str, Any]], **fields: Any) -> Path:
    suite = tmp_path / "suite"
    config: dict[str, Any] = {
        "name": "preflight",
        "benchmark": "perception",
        "suite": str(suite if suite.is_dir() else write_suite(suite)),
        "agent": "llm",
        "models": models,
        "llm": {"retry": FAST},
        "output": str(tmp_path / "run"),
    }
    config.update(fields)
    path = tmp_path / "sweep.yaml"
    path.write_text(yaml.safe_dump(config))
    return path


def only_probes(server: OpenAIServer) -> list[str]:
    """The models the server was asked about, each request checked to be the probe (one message, one token)."""
    for request in server.requests:
        assert request.body["messages"] == PROBE_MESSAGES and request.body["max_tokens"] == 1, request.body
        assert request.headers["authorization"] == f"Bearer {KEY}"
    return [request.body["model"] for request in server.requests]


@pytest.mark.parametrize(
    ("broken", "line", "probed"),
    [
        (
            model("nokey", api_key_env=UNSET_ENV, temperature=0),
            f"nokey (openai/gpt-4o-mini): model_auth: environment variable {UNSET_ENV} (its API key) is not set",
            [],
        ),
        (
            model("nobase", api_base_env="PREFLIGHT_TEST_UNSET_BASE"),
            "nobase (openai/gpt-4o-mini): model_bad_request: environment variable PREFLIGHT_TEST_UNSET_BASE "
            "(its base URL) is not set",
            [],
        ),
        (
            model("garbled", api_base_env=None, api_base="localhost-8000/v1"),
            "garbled (openai/gpt-4o-mini): model_bad_request: api_base holds no well-formed http(s) URL",
            [],
        ),
        (
            model("closed", api_base_env=None, api_base=CLOSED_BASE),
            "closed (openai/gpt-4o-mini): model_connection: after 2 attempt(s): ",
            [],
        ),
        (
            model("unknown", model="openai/missing"),
            "unknown (openai/missing): model_not_found: after 1 attempt(s): NotFoundError: ",
            ["missing"],
        ),
        (
            model("refused", model="openai/denied"),
            "refused (openai/denied): model_auth: after 1 attempt(s): AuthenticationError: ",
            ["denied"],
        ),
    ],
    ids=["key-unset", "base-unset", "base-garbled", "port-closed", "unknown-model", "key-refused"],
)
def test_a_broken_model_stops_the_sweep_before_anything_starts_naming_it(
    tmp_path: Path, server: OpenAIServer, broken: dict[str, Any], line: str, probed: list[str]
) -> None:
    assert not ray.is_initialized()
    with closed_port() as port:
        if broken.get("api_base") == CLOSED_BASE:
            broken = {**broken, "api_base": CLOSED_BASE.format(closed_port=port)}
        done = invoke("run", str(perception_sweep(tmp_path, [GOOD, broken])))
    assert done.returncode == 2, done.stdout + done.stderr
    first, *named = done.stderr.strip().splitlines()
    assert first == (
        "error: preflight: 1 of 2 model(s) cannot be called; no job was started (--skip-broken-models runs "
        "the other models' jobs):"
    )
    assert len(named) == 1 and named[0].startswith(f"  {line}"), named  # one line, naming the model and the cause
    assert sorted(only_probes(server)) == sorted(["gpt-4o-mini", *probed])  # the good model's probe, and its own
    assert not ray.is_initialized()  # the sweep's Ray (if the probe ran beside its start) is shut down
    assert not (tmp_path / "run").exists()  # nothing that would look like results
    assert KEY not in done.stdout + done.stderr


def test_the_probe_runs_while_the_sweeps_ray_starts_and_a_refusal_shuts_that_ray_down(
    tmp_path: Path, server: OpenAIServer
) -> None:
    """The server answers the probe only once the sweep's private Ray is up (in this process: ``invoke``), then
    refuses it: started after the probe, as it once was, that Ray would never come, and the probe would be
    answered without it."""
    assert not ray.is_initialized()
    ray_was_up: list[bool] = []

    def refuse_once_ray_is_up(body: dict[str, Any]) -> Behaviour:
        deadline = time.monotonic() + 60
        while not ray.is_initialized() and time.monotonic() < deadline:
            time.sleep(0.05)  # Ray has no event another thread can wait on
        ray_was_up.append(ray.is_initialized())
        return status(401)

    server.reset(refuse_once_ray_is_up)
    done = invoke("run", str(perception_sweep(tmp_path, [GOOD])))
    assert done.returncode == 2, done.stdout + done.stderr
    assert done.stderr.startswith("error: preflight: 1 of 1 model(s) cannot be called"), done.stderr
    assert "good (openai/gpt-4o-mini): model_auth" in done.stderr
    assert ray_was_up == [True]
    assert not ray.is_initialized()  # shut down with the refused sweep
    assert not (tmp_path / "run").exists()


def test_every_broken_model_gets_its_line(tmp_path: Path, server: OpenAIServer) -> None:
    models = [model("unknown", model="openai/missing"), GOOD, model("nokey", api_key_env=UNSET_ENV, temperature=0)]
    done = invoke("run", str(perception_sweep(tmp_path, models)))
    assert done.returncode == 2
    first, *named = done.stderr.strip().splitlines()
    assert first.startswith("error: preflight: 2 of 3 model(s) cannot be called")
    assert [line.split(" (")[0].strip() for line in named] == ["unknown", "nokey"]
    assert sorted(only_probes(server)) == ["gpt-4o-mini", "missing"]


def test_transient_failures_are_retried_like_episode_calls(server: OpenAIServer) -> None:
    spec = ModelSpec(**model("good"))
    server.push(status(503), status(429, retry_after=0))
    policy = RetryPolicy(max_attempts=3, initial_backoff_s=0.01, max_backoff_s=0.02)
    (check,) = check_models([spec], policy, probe=True)
    assert not check.broken and check.attempts == 3 and server.count == 3
    assert (check.input_tokens, check.output_tokens) == (14, 1)
    server.reset(lambda body: status(503))
    (check,) = check_models([spec], policy, probe=True)
    assert check.error_class == "model_provider_error" and check.attempts == 3
    assert check.cause is not None and check.cause.startswith("after 3 attempt(s): ")


def test_a_model_that_refuses_a_one_token_answer_is_asked_with_its_own_settings(server: OpenAIServer) -> None:
    spec = ModelSpec(**model("thinker", max_tokens=64))
    server.push(status(400))
    (check,) = check_models([spec], RetryPolicy(**FAST), probe=True)
    assert not check.broken and check.attempts == 2
    assert [r.body["max_tokens"] for r in server.requests] == [1, 64]
    server.reset(lambda body: status(400))
    (check,) = check_models([spec], RetryPolicy(**FAST), probe=True)
    assert check.error_class == "model_bad_request" and server.count == 2


def test_the_probe_is_on_when_a_model_names_a_key_and_settings_are_checked_either_way(
    tmp_path: Path, server: OpenAIServer
) -> None:
    def preflight(models: list[dict[str, Any]], **fields: Any) -> Any:
        config = load_sweep_config(perception_sweep(tmp_path, models, **fields))
        plan = plan_run(config)
        return run_preflight(plan, plan.jobs, None)

    keyed = preflight([GOOD])
    assert keyed.probe and keyed.where == "driver" and server.count == 1
    (check,) = keyed.models
    assert check.probed and check.cost_usd > 0 and (check.input_tokens, check.output_tokens) == (14, 1)
    keyless = preflight([model("local", api_key_env=None)])
    assert not keyless.probe and not keyless.models[0].probed and server.count == 1
    assert not preflight([GOOD], probe=False).probe and server.count == 1
    (forced,) = preflight([model("local", api_key_env=None)], probe=True).models
    assert forced.probed and forced.error_class == "model_auth"  # the OpenAI SDK wants some key; episodes would too
    unset = preflight([model("nokey", api_key_env=UNSET_ENV, temperature=0)], probe=False)
    assert unset.broken[0].error_class == "model_auth" and server.count == 1
    # Scripted agents call no model: nothing to check.
    assert preflight([GOOD], agent="oracle") is None


def test_only_the_models_jobs_call_are_checked(tmp_path: Path) -> None:
    """Synthetic episodes and scripted agents call none; an agent's helper model is called besides the sweep's."""
    helper = {"name": "pointer", "model": "openai/ui-tars", "api_key_env": KEY_ENV}
    fields: dict[str, Any] = {
        "name": "calls",
        "suite": str(SUITE_DIR),
        "tasks": {"ids": ["quiz_score", "star_shower"]},
        "models": [{"model": "openai/gpt-4o", "name": "planner", "api_key_env": KEY_ENV}],
        "episodes": {"modes": ["primitive"]},
    }

    def called(**more: Any) -> list[str]:
        path = tmp_path / "calls.yaml"
        path.write_text(yaml.safe_dump({**fields, **more}))
        config = load_sweep_config(path)
        plan = plan_run(config)
        return [spec.name for spec in ModelCalls(plan).over(plan.jobs)]

    assert called(agent="llm") == ["planner"]
    assert called(agent={"name": "planner_grounder", "params": {"grounder": helper}}) == ["planner", "pointer"]
    assert called(agent="oracle") == []  # a model label the oracle's jobs carry, never call
    assert called(agent="llm", episodes={"modes": ["primitive"], "synthetic": {}}) == []
    synthetic = {"modes": ["primitive"], "synthetic": {"tasks": ["quiz_score"]}}
    assert called(agent="llm", episodes=synthetic) == ["planner"]  # star_shower runs for real
