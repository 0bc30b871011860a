"""AWM in real sweeps: online waves, a driver killed mid-wave and resumed, and offline memory from a run dir.

The sweeps run as `scratchworld run` does (Ray, real Chromium; the one that is killed as a process of
its own) against a real local OpenAI-compatible server that plays the model: acting turns answer
``done``, the self-evaluation answers by task, and each induction answers with a numbered workflow,
so an induction that ran twice would show in the memory's text and in its digest.
"""

from __future__ import annotations

import json
import threading
from pathlib import Path
from typing import Any

import pytest
import yaml

from scratchworld_dist.memory import MEMORY_DIR, MemoryFolder
from scratchworld_dist.results import JobRow, RunStore
from scratchworld_dist.suites import load_suite
from tests.conftest import SUITE_DIR
from tests.support.openai_server import Behaviour, OpenAIServer, reply
from tests.support.sweep_driver import Driver, run_here
from workers.agents._awm_prompts import JUDGE_SYSTEM
from workers.contract import memory_digest

pytestmark = [pytest.mark.ray, pytest.mark.browser, pytest.mark.slow]

TASKS = ["star_shower", "quiz_score", "sum_two_numbers"]
"""In suite order, which is the waves' order (one task per wave)."""
JUDGED_FAILURE = "sum_two_numbers"
"""The last wave's task, which the model judges a failure."""
DONE = 'Analysis: nothing to change.\n```json\n{"api": "done", "args": {}}\n```'


class AWMModel:
    """The model behind every call of the sweep, told apart by what each call sends."""

    def __init__(self, server: OpenAIServer | None = None) -> None:
        self.server = server
        self.inductions = 0
        self.instructions = {task: load_suite(SUITE_DIR).task(task).instruction for task in TASKS}
        self.hold_on_memory = threading.Event()
        """Set to hold the first acting call that shows workflows; ``held`` is set once it is held."""
        self.held = threading.Event()
        self.lock = threading.Lock()

    def __call__(self, body: dict[str, Any]) -> Behaviour:
        messages = body.get("messages", [])
        system = str(messages[0]["content"]) if messages else ""
        if system == JUDGE_SYSTEM:
            user = str(messages[1]["content"])
            verdict = "failure" if self.instructions[JUDGED_FAILURE] in user else "success"
            return reply(f'Thoughts: the agent says it is done.\nStatus: "{verdict}"')
        if "# Successful trajectories" in system:  # the induction's single user message
            with self.lock:
                self.inductions += 1
                return reply(f"Workflow 1: routine {self.inductions}\nstep one\nstep two")
        if "# Workflow memory" in system and self.hold_on_memory.is_set() and not self.held.is_set():
            assert self.server is not None
            self.server.hold()  # this very reply waits: the wave's job is in flight
            self.held.set()
        return reply(DONE)


@pytest.fixture
def model(model_server: OpenAIServer, model_ray: int) -> AWMModel:
    """The module's server answering as the AWM model; drivers that are not killed run in the test's
    process on the module's Ray (``run_here``), which has the server in its environment."""
    model = AWMModel()
    model.server = model_server.reset(model)
    return model


def sweep(tmp_path: Path, name: str, memory: dict[str, Any], tasks: list[str] = TASKS) -> Path:
    config = {
        "name": name,
        "suite": str(SUITE_DIR),
        "tasks": {"ids": tasks},
        "agent": "awm",
        "models": [
            {
                "model": "openai/gpt-4o-mini",
                "name": "mini",
                "api_base_env": "SCRATCHWORLD_LLM_BASE_URL",
                "api_key_env": "SCRATCHWORLD_LLM_API_KEY",
            }
        ],
        "episodes": {"memory": memory, "max_steps": 5},
        "llm": {"retry": {"max_attempts": 2, "initial_backoff_s": 0.05}},
        "limits": {"retries": 0, "episode_timeout_s": 240},
        "output": str(tmp_path / name),
        "probe": False,  # these tests read the model's requests (the probe: tests/.../scheduling/test_preflight.py)
    }
    path = tmp_path / f"{name}.yaml"
    path.write_text(yaml.safe_dump(config))
    return path


def rows_by_task(run_dir: Path) -> dict[str, JobRow]:
    return {row.task_id: row for row in RunStore(run_dir).job_rows()}


def system_prompts(model: AWMModel, task: str) -> list[str]:
    """The system prompts of the acting calls of ``task``'s episodes."""
    found = []
    for request in model.server.requests if model.server is not None else []:
        system = str(request.body["messages"][0]["content"])
        if system != JUDGE_SYSTEM and "# Task\n" + model.instructions[task] in system:
            found.append(system)
    return found


def test_online_waves_learn_from_self_judged_successes_and_resume_where_they_stopped(
    tmp_path: Path, model: AWMModel, drivers: list[Driver]
) -> None:
    config = sweep(tmp_path, "online", {"kind": "online", "wave_size": 1, "seed": 3})
    store_dir = tmp_path / "online" / MEMORY_DIR
    model.hold_on_memory.set()
    driver = Driver(config)
    drivers.append(driver)
    assert model.held.wait(300), driver.log.read_text()
    (store,) = [path.name for path in store_dir.iterdir()]
    first = MemoryFolder(tmp_path / "online", store).snapshot(1)
    assert first is not None and first.snapshot.text.startswith("Workflow 1: routine 1")
    driver.kill_group()  # wave 1's job is in flight: its reply is held
    model.server.release()  # type: ignore[union-attr]
    code, log = run_here(config)
    assert code == 0, log

    rows = rows_by_task(tmp_path / "online")
    # The same waves as planned before the kill, each job shown its wave's snapshot.
    assert {task: row.memory_wave for task, row in rows.items()} == {task: n for n, task in enumerate(TASKS)}
    assert rows[TASKS[0]].memory_snapshot == memory_digest("")
    assert rows[TASKS[1]].memory_snapshot == first.digest  # read back after the kill, not induced again
    second = MemoryFolder(tmp_path / "online", store).snapshot(2)
    assert second is not None and rows[TASKS[2]].memory_snapshot == second.digest
    assert second.snapshot.text.startswith("Workflow 1: routine 2")
    assert model.inductions == 2  # one per wave after the first; the resume induced nothing twice
    # Wave 1's workflows are in wave 1's prompts (and wave 2's), never in wave 0's.
    assert all("# Workflow memory" not in system for system in system_prompts(model, TASKS[0]))
    assert all("routine 1" in system for system in system_prompts(model, TASKS[1]))
    assert all("routine 2" in system for system in system_prompts(model, TASKS[2]))
    # Learnt from the agent's own judgement, not the verdict: wave 0's job failed the tests (it only said
    # done) yet its trail was learnt; the last task, judged a failure, was proposed but is not learnable.
    assert rows[TASKS[0]].outcome == "failed"
    assert second.learned_from == [rows[TASKS[0]].job_id, rows[TASKS[1]].job_id]
    items = json.loads((store_dir / store / "items" / f"{rows[JUDGED_FAILURE].job_id}.json").read_text())
    assert [item["judged_success"] for item in items["items"]] == [False]
    # The self-evaluation and the induction are costed with the job and the snapshot.
    assert all(row.llm_calls == 2 for row in rows.values())  # one acting turn and one self-evaluation
    assert second.llm_calls == 1 and second.cost_usd > 0

    # Offline: one snapshot induced from this run's self-judged successes, shown to every job.
    offline = sweep(
        tmp_path, "offline", {"kind": "offline", "from_run": str(tmp_path / "online")}, tasks=[JUDGED_FAILURE]
    )
    code, log = run_here(offline)
    assert code == 0, log
    (row,) = rows_by_task(tmp_path / "offline").values()
    (offline_store,) = [path.name for path in (tmp_path / "offline" / MEMORY_DIR).iterdir()]
    snapshot = MemoryFolder(tmp_path / "offline", offline_store).snapshot(0)
    assert snapshot is not None and snapshot.snapshot.text.startswith("Workflow 1: routine 3")
    assert (row.memory_wave, row.memory_snapshot) == (0, snapshot.digest)
    assert set(snapshot.learned_from) == {rows[TASKS[0]].job_id, rows[TASKS[1]].job_id}
    assert "routine 3" in system_prompts(model, JUDGED_FAILURE)[-1]
