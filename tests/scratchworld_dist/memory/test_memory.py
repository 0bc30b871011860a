"""Memory shared across jobs: waves planned from the config alone, stores on disk, seeded inductions.

The keeper runs in-process here (in a sweep it is a Ray actor on the driver's node) and induces
through the harness's model client against a real local OpenAI-compatible server.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import yaml

from scratchworld_dist._errors import ConfigError
from scratchworld_dist.kinds.tasks import EpisodeMatrix, plan_jobs, read_task
from scratchworld_dist.memory import JobItems, MemoryFolder, MemoryKeeper, StoreInfo, store_name, task_waves
from scratchworld_dist.suites import load_suite
from scratchworld_dist.sweep import load_sweep_config
from tests.conftest import SUITE_DIR
from tests.support.openai_server import OpenAIServer, reply
from workers.agent_api import AgentRef
from workers.contract import MemoryItem, MemorySettings, ModelSpec, RetryPolicy, memory_digest

pytestmark = pytest.mark.usefixtures("litellm_clients")

FAST = RetryPolicy(max_attempts=2, initial_backoff_s=0.01, max_backoff_s=0.02, request_timeout_s=10, max_total_s=30)
KEY_ENV = "SCRATCHWORLD_TEST_MEMORY_KEY"
TASKS = ["quiz_score", "sum_two_numbers", "star_shower", "bounce_speedup", "power_of_number"]


@pytest.fixture(autouse=True)
def api_key(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(KEY_ENV, "sk-memory-test")


@pytest.fixture
def server() -> Iterator[OpenAIServer]:
    inductions = iter(range(1, 1000))
    with OpenAIServer(responder=lambda body: reply(f"Preamble.\nWorkflow 1: routine {next(inductions)}")) as running:
        yield running


def test_waves_follow_the_config_alone() -> None:
    assert task_waves(TASKS, MemorySettings(wave_size=2)) == {
        "quiz_score": 0,
        "sum_two_numbers": 0,
        "star_shower": 1,
        "bounce_speedup": 1,
        "power_of_number": 2,
    }
    shuffled = task_waves(TASKS, MemorySettings(wave_size=2, order="shuffled", seed=3))
    assert shuffled == task_waves(TASKS, MemorySettings(wave_size=2, order="shuffled", seed=3))
    assert list(shuffled) != TASKS and sorted(shuffled) == sorted(TASKS)
    assert list(task_waves(TASKS, MemorySettings(wave_size=2, order="shuffled", seed=4))) != list(shuffled)
    offline = MemorySettings(kind="offline", from_run=Path("/somewhere"))
    assert set(task_waves(TASKS, offline).values()) == {0}


def test_the_memory_settings_and_the_wave_are_part_of_a_jobs_identity() -> None:
    suite = load_suite(SUITE_DIR)
    contents = [read_task(suite.task(task)) for task in TASKS[:3]]
    model = ModelSpec(name="m", model="openai/gpt-4o-mini")

    def ids(memory: MemorySettings | None) -> list[str]:
        jobs = plan_jobs(
            EpisodeMatrix(
                models=[model], modes=["composite"], agent="awm", tasks=contents, seeds=[0], max_steps=10, memory=memory
            )
        )
        return [job.job_id for job in jobs]

    base = ids(MemorySettings(wave_size=1))
    assert len(set(base)) == 3
    assert ids(MemorySettings(wave_size=1)) == base  # resume finds the same jobs
    for other in (
        MemorySettings(wave_size=2),
        MemorySettings(wave_size=1, order="shuffled"),
        MemorySettings(wave_size=1, learn_from="verdict_ablation"),
        None,
    ):
        assert not set(ids(other)) & set(base), other
    (job, *_) = plan_jobs(
        EpisodeMatrix(
            models=[model],
            modes=["composite"],
            agent="awm",
            tasks=contents,
            seeds=[5],
            max_steps=10,
            memory=MemorySettings(wave_size=1),
        )
    )
    assert job.memory is not None and job.memory.store == store_name("m", "composite", 5)


def write_config(tmp_path: Path, **fields: Any) -> Path:
    config = {
        "name": "mem",
        "suite": str(SUITE_DIR),
        "agent": "awm",
        "models": [{"model": "openai/gpt-4o-mini", "name": "mini"}],
        "episodes": {"memory": {"kind": "online", "wave_size": 2}},
        **fields,
    }
    path = tmp_path / "sweep.yaml"
    path.write_text(yaml.safe_dump(config))
    return path


@pytest.mark.parametrize(
    ("fields", "fragment"),
    [
        ({"agent": "llm"}, "memory is for agents that learn across jobs"),
        ({"episodes": {"memory": None}}, "learns across jobs: give episodes.memory"),
        ({"episodes": {"memory": {"kind": "offline"}}}, "offline memory needs from_run"),
        ({"episodes": {"memory": {"wave_size": 0}}}, "episodes.memory.wave_size"),
        ({"episodes": {"memory": {"learn_from": "verdict"}}}, "episodes.memory.learn_from"),
        (
            {"agent": {"name": "planner_grounder", "params": {"grounder": {"name": "g", "model": "openai/ui-tars"}}}},
            "cannot act in composite mode",
        ),
    ],
)
def test_memory_settings_that_cannot_work_stop_the_config(
    tmp_path: Path, fields: dict[str, Any], fragment: str
) -> None:
    with pytest.raises(ConfigError, match=fragment):
        load_sweep_config(write_config(tmp_path, **fields))


def item(job: str, success: bool, task: str = "t") -> MemoryItem:
    trail = {"task": f"instruction of {job}", "trajectory": f"thought: work on {job}\naction: {{}}"}
    return MemoryItem(source=job, task_id=task, judged_success=success, content=trail)


def keeper(run_dir: Path, **settings: Any) -> MemoryKeeper:
    return MemoryKeeper(str(run_dir), AgentRef(name="awm", params={"sample_size": 2}), MemorySettings(**settings), FAST)


def spec(server: OpenAIServer) -> ModelSpec:
    return ModelSpec(name="mini", model="openai/gpt-4o-mini", api_base=server.url, api_key_env=KEY_ENV)


async def record(keeper: MemoryKeeper, wave: int, job: str, success: bool, outcome: str = "failed") -> None:
    entry = JobItems(job_id=job, wave=wave, outcome=outcome, items=[item(job, success)])  # type: ignore[arg-type]
    await keeper.record("s.composite.seed0", StoreInfo(model="mini", mode="composite", seed=0), entry)


async def test_online_snapshots_learn_from_the_agents_own_judgement_and_are_kept(
    tmp_path: Path, server: OpenAIServer
) -> None:
    memory = keeper(tmp_path)
    model = spec(server)
    first = await memory.snapshot("s.composite.seed0", 0, "composite", model)
    assert first.text == "" and server.count == 0  # nothing to learn from yet: no call
    await record(memory, 0, "job-a", success=True)  # judged a success (whatever the verdict)
    await record(memory, 0, "job-b", success=False, outcome="passed")  # the verdict passed it: not learnt
    second = await memory.snapshot("s.composite.seed0", 1, "composite", model)
    assert second.text == "Workflow 1: routine 1" and second.sources == ["job-a"]
    (request,) = server.requests
    prompt = request.body["messages"][0]["content"]
    assert "instruction of job-a" in prompt and "job-b" not in prompt
    assert "Query: Make the cat say Hello" in prompt  # the composite one-shot
    # Kept: asked again (a resume), the wave's snapshot is read back, not induced again.
    assert await memory.snapshot("s.composite.seed0", 1, "composite", model) == second
    assert server.count == 1
    # Nothing new judged worth learning from: the memory is carried, without a call.
    await record(memory, 1, "job-c", success=False)
    third = await memory.snapshot("s.composite.seed0", 2, "composite", model)
    assert (third.text, third.wave, server.count) == (second.text, 2, 1)
    saved = MemoryFolder(tmp_path, "s.composite.seed0").snapshot(1)
    assert saved is not None and saved.digest == memory_digest("Workflow 1: routine 1")
    assert saved.llm_calls == 1 and saved.reply is not None and saved.reply.startswith("Preamble.")


async def test_the_labelled_ablation_learns_from_the_verdict(tmp_path: Path, server: OpenAIServer) -> None:
    memory = keeper(tmp_path, learn_from="verdict_ablation")
    await record(memory, 0, "job-a", success=True, outcome="failed")
    await record(memory, 0, "job-b", success=False, outcome="passed")
    snapshot = await memory.snapshot("s.composite.seed0", 1, "composite", spec(server))
    assert snapshot.sources == ["job-b"]


async def test_sampling_is_seeded(tmp_path: Path, server: OpenAIServer) -> None:
    sources = []
    for run in ("one", "two", "three"):
        memory = keeper(tmp_path / run, seed=0 if run != "three" else 1)
        for name in "abcdef":
            await record(memory, 0, f"job-{name}", success=True)
        sources.append((await memory.snapshot("s.composite.seed0", 1, "composite", spec(server))).sources)
    assert len(sources[0]) == 2  # sample_size
    assert sources[0] == sources[1]
    assert sources[2] != sources[0]


@pytest.mark.parametrize(
    ("reply_text", "success"),
    [
        ('Thoughts: all there.\nStatus: "success"', True),
        ("Thoughts: fine\nstatus: Success", True),
        ('Thoughts: "success" is not the word\nStatus: "failure"', False),
        ("Thoughts: it might be a success", False),  # no Status line: not a success
        ("Status: successful", False),
    ],
)
def test_the_self_evaluation_is_read_from_its_status_line(reply_text: str, success: bool) -> None:
    from workers.agents._awm_prompts import judged_success

    assert judged_success(reply_text) is success


def test_memory_fed_by_the_verdict_is_labelled_an_ablation() -> None:
    content = read_task(load_suite(SUITE_DIR).task("quiz_score"))
    model = ModelSpec(name="m", model="openai/gpt-4o-mini")
    labels = {
        learn_from: next(
            plan_jobs(
                EpisodeMatrix(
                    models=[model],
                    modes=["composite"],
                    agent="awm",
                    tasks=[content],
                    seeds=[0],
                    max_steps=10,
                    memory=MemorySettings(learn_from=learn_from),
                )
            )
        ).agent_label
        for learn_from in ("self_judgement", "verdict_ablation")
    }
    assert labels == {"self_judgement": "awm", "verdict_ablation": "awm [verdict-fed ablation]"}
