"""With a private Ray, a sweep's workers start and open their editors while the preflight's probe waits on its
model; no job starts before the probe has answered, and a refused probe stops them again with nothing written.

A real local OpenAI-compatible server holds the probe until a worker's browser has a page open (a Chromium renderer
below the Ray: a private Ray's raylet is a child of the driver that started it), then answers or refuses it; the sweep
(one composite job of our suite, the llm agent, one step) runs in this process through the CLI, on the private
Ray it starts itself.
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import psutil
import pytest
import ray
import yaml

from scratchworld_dist.results import RunStore
from tests.conftest import SUITE_DIR
from tests.support.cli_runner import invoke
from tests.support.openai_server import Behaviour, OpenAIServer, reply, status
from workers.llm import PROBE_MESSAGES

pytestmark = [pytest.mark.browser, pytest.mark.ray, pytest.mark.slow]

BASE_ENV, KEY_ENV = "PREFLIGHT_BESIDE_BASE_URL", "PREFLIGHT_BESIDE_API_KEY"
KEY = "sk-beside-51c0e7aa"
ADD_HAT = 'Analysis: a start.\n```json\n{"api": "add_block", "args": {"blockType": "event_whenflagclicked"}}\n```'
PAGE_WAIT_S = 120.0
"""Longest the probe is held for a page (the workers open theirs within seconds of Ray, more on a loaded machine)."""


def editor_renderers() -> list[psutil.Process]:
    """The Chromium renderers of a Ray this process started (its raylet's descendants: the pages the sweep's
    workers open, not those of editors other tests of this process hold). A browser's other processes (its
    version check, crash handler, zygotes) come and go before any page opens."""
    found = []
    for raylet in _named(psutil.Process().children(recursive=True), "raylet"):
        try:
            below = raylet.children(recursive=True)
        except psutil.NoSuchProcess:
            continue
        for process in _named(below, "chromium"):
            try:
                if "--type=renderer" in process.cmdline():
                    found.append(process)
            except psutil.NoSuchProcess:
                continue
    return found


def _named(processes: list[psutil.Process], name: str) -> list[psutil.Process]:
    named = []
    for process in processes:
        try:
            if process.name() == name:
                named.append(process)
        except psutil.NoSuchProcess:
            continue
    return named


class HeldProbe:
    """Holds the probe until a worker's page is open, notes whether one was, then answers with ``probe``;
    episodes' requests get ``ADD_HAT``."""

    def __init__(self, probe: Behaviour) -> None:
        self.probe = probe
        self.page_before_answer: list[bool] = []

    def __call__(self, body: dict[str, Any]) -> Behaviour:
        if body["messages"] != PROBE_MESSAGES:
            return reply(ADD_HAT)
        deadline = time.monotonic() + PAGE_WAIT_S
        while not editor_renderers() and time.monotonic() < deadline:
            time.sleep(0.05)  # a process appearing has no event this thread can wait on
        self.page_before_answer.append(bool(editor_renderers()))
        return self.probe


@pytest.fixture
def server() -> Iterator[OpenAIServer]:
    assert gone(editor_renderers())  # an earlier sweep's, shutting down, would pass for this one's
    with OpenAIServer() as running, pytest.MonkeyPatch.context() as env:
        env.setenv(BASE_ENV, running.url)
        env.setenv(KEY_ENV, KEY)
        env.delenv("RAY_ADDRESS", raising=False)
        yield running


def composite_sweep(tmp_path: Path) -> Path:
    config: dict[str, Any] = {
        "name": "beside",
        "suite": str(SUITE_DIR),
        "tasks": {"ids": ["quiz_score"]},
        "agent": "llm",
        "models": [{"model": "openai/gpt-4o-mini", "name": "good", "api_base_env": BASE_ENV, "api_key_env": KEY_ENV}],
        "episodes": {"modes": ["composite"], "max_steps": 1},
        "limits": {"retries": 0, "episode_timeout_s": 120},
        "output": str(tmp_path / "run"),
    }
    path = tmp_path / "sweep.yaml"
    path.write_text(yaml.safe_dump(config))
    return path


def gone(processes: list[psutil.Process], within_s: float = 30.0) -> bool:
    """Whether every one of ``processes`` has exited within ``within_s`` (waited on, not slept through)."""
    _, alive = psutil.wait_procs(processes, timeout=within_s)
    return not alive


def test_the_workers_open_their_editors_while_the_probe_waits_and_the_job_starts_after_it(
    tmp_path: Path, server: OpenAIServer
) -> None:
    assert not ray.is_initialized()
    held = HeldProbe(reply("OK", prompt_tokens=14, completion_tokens=1))
    server.reset(held)
    done = invoke("run", str(composite_sweep(tmp_path)))
    assert done.returncode == 0, done.stdout + done.stderr  # the one job stops at its step limit: failed, no error
    assert held.page_before_answer == [True]  # a worker's page was open while the probe was held
    probe, *episode = server.requests
    assert probe.body["messages"] == PROBE_MESSAGES and len(episode) == 1
    assert probe.replied is not None and probe.replied <= episode[0].time  # the job waited for the answer
    (row,) = RunStore(tmp_path / "run").job_rows()
    assert (row.outcome, row.steps, row.error_class) == ("failed", 1, None)
    said = done.stderr
    assert said.index("preflight: 1 model(s) answered a probe") < said.index("admission: ")  # in the old order
    assert not ray.is_initialized()


def test_a_probe_refused_while_the_workers_open_their_editors_stops_them_leaving_nothing(
    tmp_path: Path, server: OpenAIServer
) -> None:
    assert not ray.is_initialized()
    held = HeldProbe(status(401))
    started: list[psutil.Process] = []

    def refuse(body: dict[str, Any]) -> Behaviour:
        answer = held(body)
        started.extend(editor_renderers())
        return answer

    server.reset(refuse)
    done = invoke("run", str(composite_sweep(tmp_path)))
    assert done.returncode == 2, done.stdout + done.stderr
    assert held.page_before_answer == [True] and started, (held.page_before_answer, started, done.stderr)
    assert done.stderr.startswith("error: preflight: 1 of 1 model(s) cannot be called"), done.stderr
    assert "admission" not in done.stderr  # the refusal is the first and only thing said
    assert len(server.requests) == 1  # the probe: no episode asked the model anything
    assert not ray.is_initialized()
    assert gone(started)  # the workers' pages went with their Ray
    assert not (tmp_path / "run").exists()
    assert KEY not in done.stdout + done.stderr
