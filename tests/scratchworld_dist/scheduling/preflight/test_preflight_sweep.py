"""The preflight in a sweep that runs: ``--skip-broken-models`` runs the other models' jobs, the probes' cost is
recorded with the session, a later run plans the left-out jobs again, and the jobs left in error are summed up
in the terminal with their most frequent message.

Perception jobs of the llm agent (no browser) on the module's real Ray, against a real local
OpenAI-compatible server through real LiteLLM.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
import yaml

from scratchworld_dist.results import RunStore, read_manifest
from tests.conftest import MODEL_KEY
from tests.support.openai_server import Behaviour, OpenAIServer, reply, status
from tests.support.perception_suites import CONNECTED, ITEMS, write_suite
from tests.support.sweep_driver import run_here
from workers.llm import PROBE_MESSAGES

pytestmark = [pytest.mark.ray, pytest.mark.slow]

GPT_4O_MINI = (0.15e-6, 0.6e-6)
"""LiteLLM's price per input and output token of gpt-4o-mini."""

TOO_LARGE = "this image is too large for grumpy"
TOO_SMALL = "the context is too small for this screenshot"


class Models:
    """Every model answers the probe. ``good`` answers each item right; ``grumpy`` refuses each question (a 400
    with one message for the connection question, another for the rest); ``missing`` is unknown (404) until
    ``found``."""

    def __init__(self) -> None:
        self.answers = {question: answer for *_, question, _, answer in ITEMS}
        self.found = False

    def __call__(self, body: dict[str, Any]) -> Behaviour:
        model = body["model"]
        if model == "missing" and not self.found:
            return status(404)
        if body["messages"] == PROBE_MESSAGES:
            return reply("OK", prompt_tokens=14, completion_tokens=1)
        text = next(part["text"] for part in body["messages"][-1]["content"] if part["type"] == "text")
        question = text.removeprefix("Question: ").split("\n\n")[0]
        if model == "grumpy":
            message = TOO_LARGE if question == CONNECTED else TOO_SMALL
            return status(400, body={"error": {"message": message, "type": "invalid_request_error", "code": None}})
        return reply(self.answers[question])


@pytest.fixture
def models(model_server: OpenAIServer, model_ray: int) -> Models:
    """The module's server answering as ``Models``; its address and key are in the module's Ray's environment."""
    found = Models()
    model_server.reset(found)
    return found


def sweep(tmp_path: Path) -> Path:
    llm = {"api_base_env": "SCRATCHWORLD_LLM_BASE_URL", "api_key_env": "SCRATCHWORLD_LLM_API_KEY"}
    config = {
        "name": "preflight-sweep",
        "benchmark": "perception",
        "suite": str(write_suite(tmp_path / "suite")),
        "agent": "llm",
        "models": [
            {"model": "openai/gpt-4o-mini", "name": "good", **llm},
            {"model": "openai/grumpy", "name": "grumpy", **llm},
            {"model": "openai/missing", "name": "missing", **llm},
        ],
        "llm": {"retry": {"max_attempts": 2, "initial_backoff_s": 0.05}},
        "limits": {"retries": 0, "episode_timeout_s": 60},
        "output": str(tmp_path / "run"),
    }
    path = tmp_path / "sweep.yaml"
    path.write_text(yaml.safe_dump(config))
    return path


def probes(server: OpenAIServer) -> list[str]:
    return [r.body["model"] for r in server.requests if r.body["messages"] == PROBE_MESSAGES]


def test_skipping_a_broken_model_runs_the_others_records_the_probes_and_a_later_run_plans_it_again(
    tmp_path: Path, models: Models, model_server: OpenAIServer
) -> None:
    config = sweep(tmp_path)
    code, log = run_here(config, "--skip-broken-models")
    assert code == 1, log  # grumpy's jobs are errors
    assert (
        "preflight: 1 of 3 model(s) cannot be called; their 8 job(s) are left out of this run (a run without "
        "--skip-broken-models plans them again):\n  missing (openai/missing): model_not_found: after 1 attempt(s): "
    ) in log
    flowing = " ".join(log.split())  # the progress lines wrap at the console's width
    assert "16 to run (8 left out)" in flowing and "; 8 left out (broken models)" in flowing
    rows = RunStore(tmp_path / "run").job_rows()
    assert {(r.model, r.outcome, r.error_class) for r in rows} == {
        ("good", "passed", None),
        ("grumpy", "error", "model_bad_request"),
    }
    assert len(rows) == 16
    assert sorted(probes(model_server)) == ["gpt-4o-mini", "grumpy", "missing"]  # one each, before any job
    assert all(r.body["max_tokens"] == 1 for r in model_server.requests if r.body["messages"] == PROBE_MESSAGES)
    first_job = min(r.time for r in model_server.requests if r.body["messages"] != PROBE_MESSAGES)
    assert max(r.time for r in model_server.requests if r.body["messages"] == PROBE_MESSAGES) < first_job

    # The most frequent message of each class and model, in the terminal.
    heading = "jobs left in error, by class and model, with their most frequent message:\n"
    summary = log.split(heading, 1)[1]
    digest = summary.splitlines()[0]
    assert digest.startswith("  model_bad_request | grumpy | 7 of 8: grumpy: model_bad_request after 1 attempt(s): ")
    assert TOO_SMALL in digest and TOO_LARGE not in summary  # the rarer message only in its job's own line
    assert flowing.count(TOO_LARGE) == 1

    # The session records each probe: what it cost, and why the broken model was left out.
    manifest = read_manifest(tmp_path / "run")
    assert manifest is not None
    preflight = manifest.sessions[-1].preflight
    assert preflight is not None and preflight.probe and preflight.where == "driver"
    assert preflight.left_out_jobs == 8
    checks = {check.name: check for check in preflight.models}
    assert list(checks) == ["good", "grumpy", "missing"]
    price_in, price_out = GPT_4O_MINI
    good = checks["good"]
    assert good.probed and not good.broken and (good.input_tokens, good.output_tokens) == (14, 1)
    assert good.cost_usd == pytest.approx(14 * price_in + price_out)
    assert preflight.cost_usd == pytest.approx(good.cost_usd)  # LiteLLM has no price for the others
    assert checks["missing"].error_class == "model_not_found" and checks["missing"].cost_usd == 0
    assert manifest.sessions[-1].planned == 16

    # A run without the flag plans the left-out jobs again; without a probe its model's jobs run and succeed.
    models.found = True
    code, log = run_here(config, "--no-probe")
    assert code == 1, log  # grumpy still refuses
    assert "preflight: the keys and base URLs of 2 model(s) are set (not probed)" in log  # good's jobs are decided
    assert len(probes(model_server)) == 3  # none this time
    rows = RunStore(tmp_path / "run").job_rows()
    assert sorted(r.outcome for r in rows if r.model == "missing") == ["passed"] * 8
    again = read_manifest(tmp_path / "run")
    assert again is not None and again.sessions[-1].preflight is not None
    checked = again.sessions[-1].preflight
    assert not checked.probe and checked.left_out_jobs == 0
    assert [check.name for check in checked.models] == ["grumpy", "missing"]
    assert "model_bad_request | grumpy | 7 of 8: " in log
    for path in (tmp_path / "run").rglob("*"):
        if path.is_file():
            assert MODEL_KEY.encode() not in path.read_bytes(), path
    assert MODEL_KEY not in log
