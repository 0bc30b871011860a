"""``scratchworld list``: a suite's tasks, the registered agents, a config's and LiteLLM's models with prices,
the installed benchmarks; as text and as JSON. And click's shell completion, through its environment variable."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

from scratchworld_dist.suites import load_suite
from tests.conftest import REPO
from tests.support.cli_runner import invoke
from workers.agent_api import registered_agents


def listed(*args: str) -> list[dict[str, object]]:
    done = invoke("list", *args, "--json")
    assert done.returncode == 0, done.stderr
    rows: list[dict[str, object]] = json.loads(done.stdout)
    return rows


def test_tasks_of_a_suite() -> None:
    rows = listed("tasks", str(REPO / "tasks"))
    suite = load_suite(REPO / "tasks")
    assert [row["id"] for row in rows] == [task.id for task in suite.tasks]
    assert {row["category"] for row in rows} == {task.category for task in suite.tasks}
    text = invoke("list", "tasks", str(REPO / "tasks")).stdout.splitlines()
    assert text[0].split() == ["id", "category", "golden", "trajectory"] and len(text) == len(rows) + 1


def test_agents_and_benchmarks_are_the_registered_ones() -> None:
    benchmarks = listed("benchmarks")
    assert [row["benchmark"] for row in benchmarks][:2] == ["tasks", "drag"]
    assert all(row["title"] for row in benchmarks)
    drag = listed("agents", "--benchmark", "drag")
    assert {row["agent"] for row in drag} == set(registered_agents("drag")) and "jitter" in {r["agent"] for r in drag}
    every = listed("agents")
    assert {row["benchmark"] for row in every} == {"tasks", "drag", "perception"}  # the audit runs no agent
    assert [row["agent"] for row in every if row["benchmark"] == "tasks"] == registered_agents("tasks")
    done = invoke("list", "agents", "--benchmark", "audit")
    assert done.returncode == 2 and "no agents serve 'audit'" in done.stderr
    done = invoke("list", "agents", "--benchmark", "chess")
    assert done.returncode == 2 and "no benchmark 'chess' is installed" in done.stderr


def test_models_of_a_config_and_of_a_provider_with_prices(tmp_path: Path) -> None:
    config = tmp_path / "sweep.yaml"
    config.write_text(
        f"name: t\nsuite: {REPO / 'tasks'}\nagent: llm\n"
        "models: [{model: openai/gpt-4o-mini, name: mini}, {model: openai/not-a-model-anyone-prices}]\n"
    )
    rows = listed("models", str(config), "--provider", "openai")
    mini, unpriced = rows[0], rows[1]
    assert (mini["source"], mini["name"], mini["model"]) == (str(config), "mini", "openai/gpt-4o-mini")
    assert isinstance(mini["input_usd_per_mtok"], float) and mini["input_usd_per_mtok"] > 0
    assert mini["output_usd_per_mtok"] > mini["input_usd_per_mtok"]  # type: ignore[operator]
    assert unpriced["input_usd_per_mtok"] is None  # said as unknown, never as $0
    litellm_rows = [row for row in rows if row["source"] == "litellm"]
    assert "gpt-4o-mini" in {row["name"] for row in litellm_rows} and len(litellm_rows) > 10
    done = invoke("list", "models", "--provider", "no-such-provider")
    assert done.returncode == 2 and "LiteLLM knows no model of 'no-such-provider'" in done.stderr
    assert invoke("list", "models").returncode == 2


def complete(words: str) -> list[str]:
    """What bash completion offers for the command line ``words`` (click's ``bash_complete`` protocol)."""
    env = {**os.environ, "_SCRATCHWORLD_COMPLETE": "bash_complete", "COMP_WORDS": words}
    env["COMP_CWORD"] = str(len(words.split()) - (0 if words.endswith(" ") else 1))
    code = "import sys; sys.argv = ['scratchworld']; from scratchworld_dist.cli import main; main()"
    done = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    return [line.split(",", 1)[1] for line in done.stdout.splitlines()]


def test_shell_completion_through_click_s_environment_variable() -> None:
    env = {**os.environ, "_SCRATCHWORLD_COMPLETE": "bash_source"}
    code = "import sys; sys.argv = ['scratchworld']; from scratchworld_dist.cli import main; main()"
    script = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)
    assert "_scratchworld_completion" in script.stdout and "complete " in script.stdout
    assert {"list", "run", "regrade", "export"} <= set(complete("scratchworld "))
    assert complete("scratchworld li") == ["list"]
    assert complete("scratchworld list ") == ["agents", "benchmarks", "models", "tasks"]
    assert complete("scratchworld export x --format ") == ["leaderboard", "upstream-submission", "atif"]
    assert "--address" in complete("scratchworld regrade --a")
