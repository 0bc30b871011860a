"""A sweep's driver off a terminal: plain progress lines at an interval, each error as it happens, and every attempt
as an event in the run directory's ``events.jsonl`` (synthetic episodes on a real local Ray)."""

from __future__ import annotations

import re
from collections import Counter
from pathlib import Path

import pytest
import yaml

from scratchworld_dist.results import JobError, JobFinish, JobRetry, JobStart, SweepEnd, SweepStart, read_events
from tests.conftest import REPO
from tests.support.sweep_driver import run_here

pytestmark = pytest.mark.ray

TASKS = ["sum_two_numbers", "quiz_score"]


def write_config(tmp_path: Path, **fields: object) -> Path:
    config = {"name": "events", "suite": str(REPO / "tasks"), "agent": "oracle", "output": str(tmp_path / "run")}
    path = tmp_path / "sweep.yaml"
    path.write_text(yaml.safe_dump({**config, "tasks": {"ids": TASKS}, **fields}))
    return path


def test_errors_are_said_as_they_happen_and_every_attempt_is_an_event(tmp_path: Path, shared_ray: int) -> None:
    timing_out = write_config(
        tmp_path, episodes={"synthetic": {"duration_s": 60}}, limits={"episode_timeout_s": 1, "retries": 1}
    )
    code, out = run_here(timing_out, "--progress-interval", "0.2")  # piped: auto is plain
    assert code == 1, out
    lines = out.splitlines()
    errors = [line for line in lines if line.startswith("error: ")]
    said = Counter(
        re.sub(r"episode_timeout: .*; (retrying|no retry left)$", r"episode_timeout; \1", line) for line in errors
    )
    assert said == {
        f"error: {task} (-, oracle, composite, seed 0) attempt {attempt}: episode_timeout; {then}": 1
        for task in TASKS
        for attempt, then in ((1, "retrying"), (2, "no retry left"))
    }, out
    progress = [line for line in lines if re.match(r"^\[\d\d:\d\d:\d\d\] progress: \d+/2 done", line)]
    assert len(progress) >= 2 and progress[-1].startswith(progress[-1][:11] + "progress: 2/2 done"), out
    first_error = lines.index(errors[0])
    assert any(line in progress for line in lines[first_error:]), "errors are said before the sweep ends"

    passing = write_config(tmp_path, episodes={"synthetic": {"fail_tasks": ["quiz_score"]}})
    code, out = run_here(passing, "--force", "--progress", "none")  # the same folder: a second session
    assert code == 0, out
    assert not [line for line in out.splitlines() if "progress:" in line]

    events = read_events(tmp_path / "run")
    kinds = Counter(type(event) for event in events)
    assert kinds == {SweepStart: 2, JobStart: 6, JobRetry: 2, JobError: 2, JobFinish: 2, SweepEnd: 2}
    assert [event.session for event in events if isinstance(event, SweepStart)] == [1, 2]
    first, second = [event for event in events if isinstance(event, SweepEnd)]
    assert (first.status, first.outcomes, first.retried, first.sent) == (
        "finished", {"passed": 0, "failed": 0, "error": 2}, 2, 4,
    )  # fmt: skip
    assert second.outcomes == {"passed": 1, "failed": 1, "error": 0}
    finishes = {event.task_id: event for event in events if isinstance(event, JobFinish)}
    assert (finishes["quiz_score"].outcome, finishes["sum_two_numbers"].outcome) == ("failed", "passed")
    for event in events:  # a job's attempt starts before it ends, in the session that ran it
        if isinstance(event, JobFinish | JobRetry | JobError):
            starts = [e for e in events[: events.index(event)] if isinstance(e, JobStart)]
            assert any((s.job_id, s.attempt, s.session) == (event.job_id, event.attempt, event.session) for s in starts)
