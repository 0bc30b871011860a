"""LLM sweeps end to end: `scratchworld run` with two models against a real local OpenAI-compatible server.

The server answers like a model that follows each task's golden trajectory in composite mode
and fumbles in primitive mode (one click by element index, one unparsable reply, then done), so
both modes run in full through Ray workers, real Chromium and real LiteLLM.
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import pytest
import yaml

from scratchworld_dist.results import RunStore
from scratchworld_dist.suites import load_suite
from tests.conftest import MODEL_KEY, REPO
from tests.support.cli_runner import invoke
from tests.support.openai_server import Behaviour, OpenAIServer, reply, status
from tests.support.sweep_driver import run_here

pytestmark = [pytest.mark.ray, pytest.mark.browser, pytest.mark.slow]

SECRET = MODEL_KEY
TASK = "quiz_score"
PROMPT_TOKENS, COMPLETION_TOKENS = 1200, 80
PRICES = {"gpt-4o-mini": (0.15e-6, 0.6e-6), "gpt-4o": (2.5e-6, 10e-6)}


def answer(action: dict[str, Any]) -> str:
    return f"Analysis: next step.\n```json\n{json.dumps(action)}\n```"


class TrajectoryModel:
    """Answers from the conversation alone: the task by its instruction, the turn by the replies so far
    (in composite mode, ``turns`` steps of the golden trajectory at most, then done)."""

    def __init__(self, turns: int | None = None) -> None:
        self.turns = turns
        suite = load_suite(REPO / "tasks")
        self.tasks = {task.instruction: task.trajectory() or [] for task in (suite.task(TASK),)}

    def __call__(self, body: dict[str, Any]) -> Behaviour:
        if body["model"] == "denied":  # a key without access to this model
            return status(403)
        messages = body["messages"]
        system = messages[0]["content"]
        turn = sum(1 for m in messages if m["role"] == "assistant")
        if "drag_and_drop" in system:  # primitive mode
            if turn == 0:
                text = next(p["text"] for p in messages[-1]["content"] if p["type"] == "text")
                index = re.search(r"^(\d+)  category_menu_item  Variables ", text, re.M)
                assert index is not None
                return self._reply(answer({"api": "click", "args": {"index": int(index.group(1))}}))
            if turn == 1:
                return self._reply("I am not sure what to do next.")
            return self._reply(answer({"api": "done", "args": {}}))
        trajectory = next(t for instruction, t in self.tasks.items() if instruction in system)
        if turn < len(trajectory) and (self.turns is None or turn < self.turns):
            return self._reply(answer(trajectory[turn].model_dump(mode="json", include={"api", "args"})))
        return self._reply(answer({"api": "done", "args": {}}))

    def _reply(self, text: str) -> Behaviour:
        return reply(text, prompt_tokens=PROMPT_TOKENS, completion_tokens=COMPLETION_TOKENS)


@pytest.fixture
def server(model_server: OpenAIServer, model_ray: int) -> OpenAIServer:
    """The module's server with no request yet, answering as the golden-following model; the drivers run in
    the test's process (``run_here``) on the module's Ray."""
    return model_server.reset(TrajectoryModel())


def sweep(tmp_path: Path, name: str, **fields: Any) -> Path:
    model = {"api_base_env": "SCRATCHWORLD_LLM_BASE_URL", "api_key_env": "SCRATCHWORLD_LLM_API_KEY"}
    config: dict[str, Any] = {
        "name": name,
        "suite": str(REPO / "tasks"),
        "tasks": {"ids": [TASK]},
        "agent": "llm",
        "models": [
            {"model": "openai/gpt-4o-mini", "name": "mini", **model, "rate_limits": {"requests_per_minute": 6000}},
            {"model": "openai/gpt-4o", "name": "big", **model},
            {"model": "openai/denied", "name": "denied", **model},
        ],
        "episodes": {"modes": ["composite", "primitive"], "max_steps": 40},
        "primitive": {"ocr": "none"},
        "llm": {"history_messages": 200, "retry": {"max_attempts": 2, "initial_backoff_s": 0.05}},
        "limits": {"retries": 1, "episode_timeout_s": 240},
        "output": str(tmp_path / name),
        "probe": False,  # these tests count the model's requests (the probe: tests/.../scheduling/test_preflight.py)
    }
    config.update(fields)
    path = tmp_path / f"{name}.yaml"
    path.write_text(yaml.safe_dump(config))
    return path


def report(run_dir: Path) -> dict[str, Any]:
    done = invoke("report", str(run_dir), "--format", "json")
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


def test_two_models_run_both_modes_and_the_report_shows_tokens_and_cost(tmp_path: Path, server: OpenAIServer) -> None:
    config = sweep(tmp_path, "llm")
    code, log = run_here(config)
    assert code == 1, log  # the denied model's jobs remain errors
    all_rows = RunStore(tmp_path / "llm").job_rows()
    denied = [r for r in all_rows if r.model == "denied"]
    assert [(r.outcome, r.error_class, r.attempt) for r in denied] == [("error", "model_auth", 1)] * 2  # not retried
    assert sum(1 for r in server.requests if r.body["model"] == "denied") == 2
    rows = {(r.model, r.mode): r for r in all_rows if r.model != "denied"}
    assert {(r.eval_profile, r.eval_clock) for r in rows.values()} == {("native", "virtual")}  # our suite's defaults
    assert {key: row.outcome for key, row in rows.items()} == {
        ("mini", "composite"): "passed",
        ("big", "composite"): "passed",
        ("mini", "primitive"): "failed",
        ("big", "primitive"): "failed",
    }
    calls = {key: row.llm_calls for key, row in rows.items()}
    assert sum(calls.values()) == server.count - 2
    for (model, _), row in rows.items():
        price_in, price_out = PRICES["gpt-4o-mini" if model == "mini" else "gpt-4o"]
        assert (row.input_tokens, row.output_tokens) == (
            PROMPT_TOKENS * row.llm_calls,
            COMPLETION_TOKENS * row.llm_calls,
        )
        assert row.cost_usd == pytest.approx(row.llm_calls * (PROMPT_TOKENS * price_in + COMPLETION_TOKENS * price_out))
    assert calls[("mini", "primitive")] == 3  # click, unparsable reply, done

    by_label = {(r["label"], r["mode"]): r for r in report(tmp_path / "llm")["rows"]}
    assert by_label[next(k for k in by_label if "denied" in k[0] and k[1] == "composite")]["errors"] == 1
    for (model, mode), row in rows.items():
        reported = next(r for (label, m), r in by_label.items() if r["model"] == model and m == mode)
        assert reported["input_tokens"] == row.input_tokens and reported["output_tokens"] == row.output_tokens
        assert reported["cost_usd"] == pytest.approx(row.cost_usd)

    # Trajectories keep prompts, replies and each screenshot once; no file of the run holds the key.
    primitive = rows[("mini", "primitive")]
    folder = tmp_path / "llm" / str(primitive.artifact_dir)
    steps = [json.loads(line) for line in (folder / "trajectory.jsonl").read_text().splitlines()]
    assert steps[0]["prompt"][0]["role"] == "system" and steps[1]["reply"] == "I am not sure what to do next."
    refs = {
        p["sha256"]
        for s in steps
        for m in s["prompt"]
        if isinstance(m["content"], list)
        for p in m["content"]
        if p["type"] == "image_ref"
    }
    assert {path.stem for path in (folder / "images").iterdir()} == refs
    for path in (tmp_path / "llm").rglob("*"):
        if path.is_file():
            assert SECRET.encode() not in path.read_bytes(), path
    assert SECRET not in log
    assert all(r.headers["authorization"] == f"Bearer {SECRET}" for r in server.requests)


@pytest.mark.usefixtures("server")
def test_a_budget_stops_new_jobs_and_the_report_says_so(tmp_path: Path) -> None:
    config = sweep(
        tmp_path,
        "budget",
        models=[
            {
                "model": "openai/gpt-4o",
                "api_base_env": "SCRATCHWORLD_LLM_BASE_URL",
                "api_key_env": "SCRATCHWORLD_LLM_API_KEY",
            }
        ],
        episodes={"modes": ["composite"], "max_steps": 40},
        seeds=[0, 1, 2],
        limits={"budget_usd": 0.001, "max_in_flight": 1, "retries": 0},
    )
    code, log = run_here(config)
    assert code == 0, log
    rows = RunStore(tmp_path / "budget").job_rows()
    assert len(rows) == 1 and rows[0].cost_usd > 0.001  # the job that crossed the budget finishes; no other starts
    text = invoke("report", str(tmp_path / "budget")).stdout
    assert "Stopped by budget" in text and "2 job(s) not started" in text
    # Resuming spends nothing more: the budget counts what the directory already holds.
    code, log = run_here(config)
    assert code == 0 and "2 job(s) not started" in log
    assert len(RunStore(tmp_path / "budget").job_rows()) == 1


def test_a_rerun_with_the_model_cache_replays_every_reply_at_no_cost(tmp_path: Path, server: OpenAIServer) -> None:
    """The model selects the sprite, then stops: actions whose answers hold no generated ids (the page names
    new blocks and variables by the clock, so a conversation past one differs between runs and misses)."""
    server.reset(TrajectoryModel(turns=1))
    model = {"api_base_env": "SCRATCHWORLD_LLM_BASE_URL", "api_key_env": "SCRATCHWORLD_LLM_API_KEY"}
    fields: dict[str, Any] = {"models": [{"model": "openai/gpt-4o", "temperature": 0, **model}]}
    fields["episodes"] = {"modes": ["composite"], "max_steps": 40}
    first = sweep(tmp_path, "cached-first", model_cache={"dir": "model-cache"}, **fields)
    code, log = run_here(first)
    assert code == 0, log
    assert "\n1 worker(s) x 1 page(s) on " in log  # one job: no other slot's browser starts
    (made,) = RunStore(tmp_path / "cached-first").job_rows()
    assert (made.outcome, made.llm_calls, made.llm_cache_hits, server.count) == ("failed", 2, 0, 2)
    assert made.cost_usd > 0
    stored = list((tmp_path / "model-cache").glob("*/*.json"))
    assert len(stored) == 2 and all(SECRET.encode() not in path.read_bytes() for path in stored)

    # Another run (another directory), given the same folder on the command line: every reply is replayed.
    second = sweep(tmp_path, "cached-again", **fields)
    code, log = run_here(second, "--model-cache", str(tmp_path / "model-cache"))
    assert code == 0, log
    assert "1 kept warm from this process's last sweep" in " ".join(log.split())  # the first run's, browser open
    (replayed,) = RunStore(tmp_path / "cached-again").job_rows()
    assert server.count == 2  # no request reached the server
    assert replayed.job_id == made.job_id  # the cache is not part of a job's identity
    assert (replayed.outcome, replayed.llm_calls, replayed.llm_cache_hits, replayed.cost_usd) == ("failed", 2, 2, 0.0)
    assert (replayed.input_tokens, replayed.output_tokens) == (made.input_tokens, made.output_tokens)
    steps = RunStore(tmp_path / "cached-again").read_table("steps").to_pylist()
    assert [s["llm_cache_hits"] for s in steps] == [1, 1]
    trajectory = tmp_path / "cached-again" / str(replayed.artifact_dir) / "trajectory.jsonl"
    assert [json.loads(line)["llm_cache_hits"] for line in trajectory.read_text().splitlines()] == [1, 1]

    (row,) = report(tmp_path / "cached-again")["rows"]
    assert (row["llm_cache_hits"], row["llm_cache_calls"], row["cost_usd"]) == (2, 2, 0.0)
    text = invoke("report", str(tmp_path / "cached-again")).stdout
    assert "| 2/2 (100.0%) |" in text and "Cache hits:" in text
    first_text = invoke("report", str(tmp_path / "cached-first")).stdout
    assert "| 0/2 (0.0%) |" in first_text  # the first run had the cache too, and no hit
