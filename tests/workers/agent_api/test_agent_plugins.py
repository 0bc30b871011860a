"""Agents brought by users: the example of docs/own-agent.md, installed as a package of its own, found and run.

The package is built from that page's code block as printed and installed with pip into a
folder of its own (put on the path), so the venv is left as it was. Loading a config resolves
the agent and validates its params; a sweep runs it through Ray, real Chromium and a real
local OpenAI-compatible server, in both modes, with its calls retried, paced and costed.
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import yaml

from scratchworld_dist._errors import ConfigError
from scratchworld_dist.kinds.tasks import EpisodeMatrix, plan_jobs
from scratchworld_dist.results import RunStore
from scratchworld_dist.suites import load_suite
from scratchworld_dist.sweep import load_sweep_config
from tests.conftest import REPO
from tests.support.openai_server import Behaviour, OpenAIServer, reply, status
from tests.support.sweep_driver import Driver, run
from workers.agent_api import AgentBase, agent_class, agent_code

TASK = "quiz_score"
PROMPT_TOKENS, COMPLETION_TOKENS = 900, 60
GPT_4O_MINI = (0.15e-6, 0.6e-6)
KEY = "sk-plugin-test-7c1f0e93ad"

PYPROJECT = """
[build-system]
requires = ["setuptools"]
build-backend = "setuptools.build_meta"

[project]
name = "my-agents"
version = "1.0.0"

[project.entry-points."scratchworld.agents"]
json_agent = "my_agents:JsonAgent"
"""


def readme_example() -> str:
    """The Python block of docs/own-agent.md ("Write your own agent"), exactly as printed."""
    section = (REPO / "docs" / "own-agent.md").read_text().split("\n## ", 1)[0]
    match = re.search(r"```python\n(.*?)```", section, re.S)
    assert match is not None, "docs/own-agent.md has no example agent"
    return match.group(1)


def install(package: Path, site: Path) -> None:
    command = [sys.executable, "-m", "pip", "install", "--quiet", "--no-deps", "--no-build-isolation"]
    subprocess.run([*command, "--target", str(site), str(package)], check=True, capture_output=True, timeout=300)


@pytest.fixture(scope="module")
def plugin(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The folder the plugin package is installed into (its dist-info carries the entry point)."""
    root = tmp_path_factory.mktemp("plugin")
    (root / "pkg" / "my_agents").mkdir(parents=True)
    (root / "pkg" / "pyproject.toml").write_text(PYPROJECT)
    (root / "pkg" / "my_agents" / "__init__.py").write_text(readme_example())
    install(root / "pkg", root / "site")
    return root / "site"


@pytest.fixture
def on_path(plugin: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.syspath_prepend(str(plugin))
    monkeypatch.setenv("PYTHONPATH", str(plugin))  # for drivers and their Ray workers
    return plugin


def config(tmp_path: Path, name: str = "plugin", **fields: Any) -> Path:
    model = {"api_base_env": "SCRATCHWORLD_LLM_BASE_URL", "api_key_env": "SCRATCHWORLD_LLM_API_KEY"}
    body: dict[str, Any] = {
        "name": name,
        "suite": str(REPO / "tasks"),
        "tasks": {"ids": [TASK]},
        "agent": {"name": "json_agent", "params": {"style": "One JSON object, please."}, "label": "json"},
        "models": [{"model": "openai/gpt-4o-mini", "name": "mini", **model}],
        "episodes": {"modes": ["composite", "primitive"], "max_steps": 30},
        "primitive": {"ocr": "none"},
        "llm": {"retry": {"max_attempts": 3, "initial_backoff_s": 0.05, "max_backoff_s": 0.1}},
        "limits": {"retries": 0, "episode_timeout_s": 240},
        "output": str(tmp_path / name),
        "probe": False,  # these tests count the model's requests (the probe: tests/.../scheduling/test_preflight.py)
    }
    body.update(fields)
    path = tmp_path / f"{name}.yaml"
    path.write_text(yaml.safe_dump(body))
    return path


@pytest.mark.usefixtures("on_path")
def test_an_installed_plugin_is_found_by_entry_point_and_by_module_path(tmp_path: Path) -> None:
    loaded = load_sweep_config(config(tmp_path))
    assert loaded.agent.name == "json_agent" and loaded.agent.params == {"style": "One JSON object, please."}
    cls = agent_class("json_agent")
    assert cls is agent_class("my_agents:JsonAgent") and cls.needs_model
    # Outside this repository: its code and version are part of each job's identity.
    code = agent_code(cls)
    assert code is not None and agent_code(agent_class("llm")) is None
    by_module = load_sweep_config(config(tmp_path, agent={"name": "my_agents:JsonAgent"}))
    assert by_module.agent.name == "my_agents:JsonAgent"


@pytest.mark.usefixtures("on_path")
@pytest.mark.parametrize(
    ("agent", "fragment"),
    [
        ({"name": "json_agent", "params": {"style": 3}}, "agent json_agent rejects its params: style: Input should be"),
        ({"name": "json_agent", "params": {"colour": "red"}}, "rejects its params: unknown colour (accepted: style)"),
        (
            {"name": "no_such_agent"},
            "is not registered for the tasks benchmark (registered: awm, human, json_agent, llm, noop, oracle",
        ),
        ({"name": "my_agents:Missing"}, "agent my_agents:Missing: module my_agents has no Missing"),
        ({"name": "no_such_module:Agent"}, "agent no_such_module:Agent cannot be imported: ModuleNotFoundError"),
        ({"name": "json:dumps"}, "agent json:dumps is not a class"),
        ({"name": "pathlib:Path"}, "agent pathlib:Path lacks start, act, finish"),
        ({"name": "rm -rf"}, "is neither a registered agent name nor package.module:Class"),
        ({"name": f"{__name__}:Snooper"}, "declares privileged = True, which would show it the solution"),
    ],
)
def test_an_agent_that_cannot_run_stops_the_config(tmp_path: Path, agent: dict[str, Any], fragment: str) -> None:
    with pytest.raises(ConfigError) as caught:
        load_sweep_config(config(tmp_path, agent=agent))
    message = str(caught.value)
    assert fragment in message and "\n" not in message, message


@pytest.mark.usefixtures("on_path")
def test_params_and_code_change_the_job_identity(tmp_path: Path, plugin: Path) -> None:
    content = read_quiz()
    jobs = {}
    for label, params, code in [
        ("base", {}, "a"),
        ("relabelled", {}, "a"),
        ("params", {"style": "terse"}, "a"),
        ("code", {}, "b"),
    ]:
        ref = {"name": "json_agent", "params": params, "label": label}
        (job,) = plan_jobs(
            EpisodeMatrix(
                models=[None], modes=["composite"], agent=ref, tasks=[content], seeds=[0], max_steps=10, agent_code=code
            )
        )  # type: ignore[arg-type]
        jobs[label] = job.job_id
    assert jobs["base"] == jobs["relabelled"]  # a label only names it in reports
    assert len({jobs["base"], jobs["params"], jobs["code"]}) == 3
    # Editing the installed module changes the digest the driver plans with.
    module = plugin / "my_agents" / "__init__.py"
    before = agent_code(agent_class("json_agent"))
    original = module.read_text()
    try:
        module.write_text(original + "\n# a local change\n")
        assert agent_code(agent_class("json_agent")) != before
    finally:
        module.write_text(original)


class Snooper(AgentBase):
    """A plugin that claims the oracles' privileges."""

    privileged = True


class LiveSnooper(AgentBase):
    """A plugin that claims to act live, as a person does (the live editor, its actions never performed)."""

    acts_live = True


def read_quiz() -> Any:
    from scratchworld_dist.kinds.tasks import read_task

    return read_task(load_suite(REPO / "tasks").task(TASK))


class JsonModel:
    """Answers the documented agent: the golden trajectory in composite mode, a click then done in primitive
    mode; the very first call is refused with a 429, which the harness must retry."""

    def __init__(self) -> None:
        self.trajectory = [a.model_dump(include={"api", "args"}) for a in read_quiz().payload.golden_trajectory]
        self.refused = False

    def __call__(self, body: dict[str, Any]) -> Behaviour:
        if not self.refused:
            self.refused = True
            return status(429, retry_after=0)
        messages = body["messages"]
        turn = sum(1 for m in messages if m["role"] == "assistant")
        if "## Blocks Pseudocode" in messages[1]["content"]:  # composite mode
            action = self.trajectory[turn] if turn < len(self.trajectory) else {"api": "done", "args": {}}
        elif turn == 0:
            variables = re.search(r"^(\d+)  category_menu_item  Variables ", messages[1]["content"], re.M)
            assert variables is not None
            action = {"api": "click", "args": {"index": int(variables.group(1))}}
        else:
            action = {"api": "done", "args": {}}
        return reply(json.dumps(action), prompt_tokens=PROMPT_TOKENS, completion_tokens=COMPLETION_TOKENS)


@pytest.fixture
def server(monkeypatch: pytest.MonkeyPatch) -> Iterator[OpenAIServer]:
    with OpenAIServer(responder=JsonModel()) as running:
        monkeypatch.setenv("SCRATCHWORLD_LLM_BASE_URL", running.url)
        monkeypatch.setenv("SCRATCHWORLD_LLM_API_KEY", KEY)
        yield running


@pytest.mark.ray
@pytest.mark.browser
@pytest.mark.usefixtures("on_path")
@pytest.mark.slow
@pytest.mark.timeout(600 + 300)  # its run is bounded at 600 s
def test_the_readme_agent_runs_both_modes_with_calls_retried_paced_and_costed(
    tmp_path: Path, server: OpenAIServer, drivers: list[Driver]
) -> None:
    paced = {"requests_per_minute": 60, "burst_s": 1.0}  # one call a second, across both workers
    models = [
        {
            "model": "openai/gpt-4o-mini",
            "name": "mini",
            "api_base_env": "SCRATCHWORLD_LLM_BASE_URL",
            "api_key_env": "SCRATCHWORLD_LLM_API_KEY",
            "rate_limits": paced,
        }
    ]
    code, log = run(drivers, config(tmp_path, models=models), timeout=600)
    assert code == 0, log
    rows = {row.mode: row for row in RunStore(tmp_path / "plugin").job_rows()}
    assert {mode: (row.agent, row.outcome) for mode, row in rows.items()} == {
        "composite": ("json", "passed"),
        "primitive": ("json", "failed"),  # one click, then done: determinate, not an error
    }
    # Retried: the 429 was one more request than the calls the rows count.
    assert [r.behaviour.code for r in server.requests].count(429) == 1
    assert sum(row.llm_calls for row in rows.values()) == server.count - 1
    # Costed: LiteLLM's price of gpt-4o-mini for the billed tokens.
    price_in, price_out = GPT_4O_MINI
    for row in rows.values():
        assert (row.input_tokens, row.output_tokens) == (
            PROMPT_TOKENS * row.llm_calls,
            COMPLETION_TOKENS * row.llm_calls,
        )
        assert row.cost_usd == pytest.approx(row.llm_calls * (PROMPT_TOKENS * price_in + COMPLETION_TOKENS * price_out))
    # Paced by the cluster's limiter (one grant a second for both workers): the calls, that unpaced would
    # come every ~0.4 s, are spread over at least about a second each (arrival times jitter with load).
    times = sorted(r.time for r in server.requests)
    assert times[-1] - times[0] >= 0.8 * (len(times) - 2), [round(t - times[0], 2) for t in times]
    # Logged: the trajectory holds what each step added to the conversation, and the raw reply.
    composite = rows["composite"]
    folder = tmp_path / "plugin" / str(composite.artifact_dir)
    steps = [json.loads(line) for line in (folder / "trajectory.jsonl").read_text().splitlines()]
    assert [m["role"] for m in steps[0]["prompt"]] == ["system", "user"]
    assert [m["role"] for m in steps[1]["prompt"]] == ["user"]
    assert json.loads(steps[0]["reply"])["api"] == JsonModel().trajectory[0]["api"]
    for path in (tmp_path / "plugin").rglob("*"):
        if path.is_file():
            assert KEY.encode() not in path.read_bytes(), path
