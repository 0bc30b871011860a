"""A human baseline as a sweep: ``agent: human`` plans real-clock jobs named by their participant, takes the
whole local node, and refuses what a person at a screen cannot do; ``scratchworld play`` refuses bad input
before anything starts."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
from pydantic import ValidationError

from scratchworld_dist.scheduling import admitted_slots, exclusive
from scratchworld_dist.sweep import Limits, SweepConfig, plan_run
from tests.support.cli_runner import invoke

REPO = Path(__file__).resolve().parents[3]
TASKS = ["bouncing_ball_stuck", "quiz_score"]


def config(participant: str = "ada", **fields: Any) -> SweepConfig:
    body: dict[str, Any] = {
        "name": "human",
        "suite": str(REPO / "tasks"),
        "tasks": {"ids": TASKS},
        "agent": {"name": "human", "params": {"participant": participant}},
        "episodes": {"modes": ["primitive"], "max_steps": 200},
        **fields,
    }
    return SweepConfig.model_validate(body)


def test_human_jobs_run_on_the_wall_clock_and_two_people_are_two_jobs() -> None:
    ada, bob = plan_run(config("ada")).jobs, plan_run(config("bob")).jobs
    assert len(ada) == len(bob) == len(TASKS)
    assert {job.body.page_clock for job in ada} == {"real"}  # type: ignore[attr-defined]
    assert [job.model for job in ada] == [None, None]  # a person calls no model
    assert {job.job_id for job in ada}.isdisjoint(job.job_id for job in bob)
    assert [job.job_id for job in plan_run(config("ada")).jobs] == [job.job_id for job in ada]


def test_a_human_job_takes_the_whole_local_node() -> None:
    said: list[str] = []
    jobs = plan_run(config()).jobs
    assert exclusive(jobs)
    assert admitted_slots(Limits(browser_slots=4), jobs, "h", said.append) == 1
    assert said == ["admission: 1 browser slot (a person works on each job: one at a time, on this machine)"]
    oracle = plan_run(config(agent="oracle")).jobs
    assert not exclusive(oracle)
    assert admitted_slots(Limits(browser_slots=4), oracle, "h", said.append) == 4


@pytest.mark.parametrize(
    ("fields", "fragment"),
    [
        ({"episodes": {"modes": ["primitive"], "episode_clock": {"mode": "virtual"}}}, "episode_clock must be real"),
        ({"ray": {"address": "10.0.0.1:6379"}}, "runs on this machine, one job at a time: drop ray.address"),
        ({"agent": {"name": "human"}}, "participant: Field required"),
        ({"agent": {"name": "human", "params": {"participant": "Ada Lovelace"}}}, "participant: String should match"),
    ],
)
def test_what_a_person_cannot_do_is_refused(fields: dict[str, Any], fragment: str) -> None:
    with pytest.raises(ValidationError) as caught:
        config(**fields)
    assert fragment in str(caught.value)


def test_play_refuses_bad_input_before_anything_starts(tmp_path: Path) -> None:
    unknown = invoke("play", str(REPO / "tasks"), "no_such_task", "--output", str(tmp_path / "a"))
    assert unknown.returncode == 2
    assert "no_such_task" in unknown.stderr
    bad_name = invoke("play", str(REPO / "tasks"), TASKS[0], "--participant", "a b", "--output", str(tmp_path / "b"))
    assert bad_name.returncode == 2
    assert "--participant" in bad_name.stderr
    assert not (tmp_path / "a").exists()
    assert not (tmp_path / "b").exists()
