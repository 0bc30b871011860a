"""On a cluster the preflight runs where the workers read keys: in a task on a node with browser slots.

A real cluster of `ray start` processes (the head without browsers, one node with a browser slot whose
environment holds the model's key and address) and a driver whose environment holds neither: the node's
probes pass and its jobs run; a model the server does not know stops the run naming the node and the model.
"""

from __future__ import annotations

import subprocess
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import yaml

from scratchworld_dist.results import RunStore, read_manifest
from tests.conftest import REPO
from tests.support.openai_server import Behaviour, OpenAIServer, reply, status
from tests.support.perception_suites import ITEMS, write_suite
from tests.support.ray_cluster import Cluster
from tests.support.sweep_driver import SCRATCHWORLD
from workers.llm import PROBE_MESSAGES

pytestmark = [pytest.mark.ray, pytest.mark.slow, pytest.mark.timeout(2 * 600 + 300)]  # two runs of at most 600 s

BASE_ENV, KEY_ENV = "PREFLIGHT_NODE_BASE_URL", "PREFLIGHT_NODE_API_KEY"
KEY = "sk-node-only-4f0a"
MODEL = {"api_base_env": BASE_ENV, "api_key_env": KEY_ENV}


def answer(body: dict[str, Any]) -> Behaviour:
    if body["model"] == "missing":
        return status(404)
    if body["messages"] == PROBE_MESSAGES:
        return reply("OK", prompt_tokens=14, completion_tokens=1)
    text = next(part["text"] for part in body["messages"][-1]["content"] if part["type"] == "text")
    question = text.removeprefix("Question: ").split("\n\n")[0]
    return reply(next(answer for *_, asked, _, answer in ITEMS if asked == question))


@pytest.fixture
def cluster(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Iterator[tuple[Cluster, OpenAIServer]]:
    """A head without browsers and one node with a slot, the server's address and the key in its environment only."""
    with OpenAIServer(responder=answer) as server:
        running = Cluster(tmp_path)
        try:
            running.head()
            with monkeypatch.context() as node_env:
                node_env.setenv(BASE_ENV, server.url)
                node_env.setenv(KEY_ENV, KEY)
                running.node(REPO, browsers=1)
            monkeypatch.delenv(BASE_ENV, raising=False)
            monkeypatch.delenv(KEY_ENV, raising=False)
            yield running, server
        finally:
            running.stop()


def sweep(tmp_path: Path, cluster: Cluster, models: list[str]) -> Path:
    suite = tmp_path / "suite"
    config = {
        "name": "preflight-cluster",
        "benchmark": "perception",
        "suite": str(suite if suite.is_dir() else write_suite(suite)),
        "agent": "llm",
        "tasks": {"ids": ["c-yes", "f-num"]},
        "models": [{"model": f"openai/{name}", "name": name, **MODEL} for name in models],
        "llm": {"retry": {"max_attempts": 2, "initial_backoff_s": 0.05}},
        "output": str(tmp_path / "run"),
        "ray": {"address": cluster.address, "connect_timeout_s": 60},
    }
    path = tmp_path / "sweep.yaml"
    path.write_text(yaml.safe_dump(config))
    return path


def run(config: Path, cluster: Cluster) -> subprocess.CompletedProcess[str]:
    """The driver outside any checkout (Ray puts its working directory first on the workers' path)."""
    return subprocess.run(
        [SCRATCHWORLD, "run", str(config)], cwd=config.parent, env=cluster.env(), capture_output=True, text=True,
        timeout=600,
    )  # fmt: skip


def test_the_node_checks_the_models_with_its_own_environment(
    tmp_path: Path, cluster: tuple[Cluster, OpenAIServer]
) -> None:
    running, server = cluster
    refused = run(sweep(tmp_path, running, ["gpt-4o-mini", "missing"]), running)
    assert refused.returncode == 2, refused.stdout + refused.stderr
    first, *named = refused.stderr.strip().splitlines()[-2:]
    assert first.startswith("error: preflight on ") and "1 of 2 model(s) cannot be called" in first
    assert named == [named[0]] and named[0].startswith("  missing (openai/missing): model_not_found: ")
    assert sorted(r.body["model"] for r in server.requests) == ["gpt-4o-mini", "missing"]  # the probes only
    assert not (tmp_path / "run").exists()

    done = run(sweep(tmp_path, running, ["gpt-4o-mini"]), running)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "model(s) answered a probe" in done.stderr
    rows = RunStore(tmp_path / "run").job_rows()
    assert sorted(row.outcome for row in rows) == ["passed", "passed"]
    manifest = read_manifest(tmp_path / "run")
    assert manifest is not None
    preflight = manifest.sessions[-1].preflight
    assert preflight is not None and preflight.where.startswith(manifest.sessions[-1].nodes[0].hostname)
    assert KEY not in done.stdout + done.stderr
