"""The sweep engine end to end with a real local Ray.

Synthetic (browserless) episodes exercise scheduling, faults and resume quickly; one sweep runs
real episodes in Chromium. A driver that is killed, whose workers are killed or must see another
environment, or that joins another cluster is `scratchworld run` in a subprocess, in its own process
group, killed after the test so its Ray helpers never outlive it; the others run in this process on
one Ray for the module (the ``shared_ray`` fixture).
"""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import time
from collections import Counter
from pathlib import Path

import pytest
import yaml

from scratchworld_dist.reports._runs import load_run
from scratchworld_dist.results import RunStore, effective_rows, read_manifest
from scratchworld_dist.suites import load_suite
from tests.conftest import REPO, copy_page_files, link_installed_packages
from tests.support.cli_runner import invoke
from tests.support.sweep_driver import SCRATCHWORLD, Driver, run, run_here
from workers.node import OWN_FILES
from workers.node._fingerprint import EDITOR_LOCK_FILES

pytestmark = pytest.mark.ray

TASKS = ["sum_two_numbers", "bouncing_ball_stuck", "quiz_score", "star_shower"]


def write_config(tmp_path: Path, **fields: object) -> Path:
    config = {"name": "t", "suite": str(REPO / "tasks"), "agent": "oracle", "output": str(tmp_path / "run")}
    config.update(fields)
    path = tmp_path / "sweep.yaml"
    path.write_text(yaml.safe_dump(config))
    return path


def committed_lines(run_dir: Path) -> int:
    journal = run_dir / "journal"
    return sum(len(p.read_bytes().splitlines()) for p in journal.glob("*.jsonl")) if journal.exists() else 0


def wait_for(condition: object, timeout: float, what: str) -> None:
    deadline = time.monotonic() + timeout
    while not condition():  # type: ignore[operator]
        if time.monotonic() > deadline:
            raise AssertionError(f"timed out waiting for {what}")
        time.sleep(0.1)


@pytest.mark.slow
def test_resume_after_killing_the_driver_loses_and_duplicates_nothing(tmp_path: Path, drivers: list[Driver]) -> None:
    config = write_config(tmp_path, seeds=5, episodes={"synthetic": {"duration_s": 0.3, "fail_tasks": ["quiz_score"]}})
    run_dir = tmp_path / "run"
    first = Driver(config)
    drivers.append(first)
    wait_for(lambda: committed_lines(run_dir) >= 8, 120, "the first committed jobs")
    os.kill(first.process.pid, signal.SIGKILL)  # the driver only; its Ray helpers are reaped later
    first.process.wait()
    before = {row.job_id: row for row in RunStore(run_dir).job_rows()}
    assert 8 <= len(before) < 60

    code, out = run(drivers, config)
    assert code == 0, out
    assert f"{len(before)} decided before" in out

    rows = RunStore(run_dir).job_rows()
    assert len(rows) == 60  # 12 tasks x 5 seeds, each exactly once
    assert len({row.job_id for row in rows}) == 60
    after = {row.job_id: row for row in rows}
    assert all(after[job] == row for job, row in before.items())  # committed rows untouched
    outcomes = Counter(row.outcome for row in rows)
    assert outcomes == {"passed": 55, "failed": 5}
    assert not list((run_dir / "journal").glob("*.jsonl"))  # compacted at the end

    code, out = run(drivers, config)  # a third run has nothing left to do
    assert code == 0
    assert "60 already decided, 0 to run" in " ".join(out.split())


@pytest.mark.slow
def test_jobs_of_a_killed_worker_are_rescheduled(tmp_path: Path, drivers: list[Driver]) -> None:
    # Workers restart in seconds (imports, browser); Ray fails calls sent to one meanwhile.
    config = write_config(
        tmp_path, seeds=2, episodes={"synthetic": {"duration_s": 1.0, "startup_s": 5}}, limits={"browser_slots": 2}
    )
    run_dir = tmp_path / "run"
    driver = Driver(config)
    drivers.append(driver)
    wait_for(lambda: committed_lines(run_dir) >= 2, 120, "the first committed jobs")
    victim = RunStore(run_dir).job_rows()[0].worker_pid
    assert victim is not None
    os.kill(victim, signal.SIGKILL)  # as the OOM killer would, mid-episode

    code, out = driver.wait()
    assert code == 0, out
    rows = RunStore(run_dir).job_rows()
    died = [row for row in rows if row.error_class == "worker_died"]
    # Its in-flight job is recorded; no job is sent to it until it is back.
    assert len(died) == 1, [(row.task_id, row.attempt, row.started_at) for row in died]
    assert all(row.outcome == "error" and row.attempt == 1 for row in died)
    effective = list(effective_rows(rows))
    assert len(effective) == 24
    assert {row.outcome for row in effective} == {"passed"}
    retried = {row.job_id for row in died}
    assert {(row.job_id, row.attempt) for row in rows if row.job_id in retried} >= {(job, 2) for job in retried}
    later = [row for row in rows if row.finished_at > died[0].finished_at]
    assert victim not in {row.worker_pid for row in later}
    (index,) = {row.worker_index for row in rows if row.worker_pid == victim}
    assert index in {row.worker_index for row in later}  # the restarted worker takes jobs again


@pytest.mark.slow
def test_jobs_spread_over_a_two_node_cluster(tmp_path: Path, drivers: list[Driver]) -> None:
    from ray.cluster_utils import Cluster

    cluster = Cluster(
        initialize_head=True,
        head_node_args={"num_cpus": 1, "resources": {"browser": 1}, "include_dashboard": False},
    )
    try:
        cluster.add_node(num_cpus=1, resources={"browser": 1})
        cluster.wait_for_nodes()
        config = write_config(tmp_path, seeds=2, episodes={"synthetic": {"duration_s": 0.5}})
        code, out = run(drivers, config, "--address", cluster.address)
        assert code == 0, out
        assert "2 worker(s) x 1 page(s) on 2 browser slot(s)" in out
        rows = RunStore(tmp_path / "run").job_rows()
        assert len(rows) == 24
        nodes = Counter(row.worker_node for row in rows)
        assert len(nodes) == 2, nodes
        assert min(nodes.values()) >= 6  # both nodes did a fair share
    finally:
        cluster.shutdown()


def edited_editor(tmp_path: Path) -> Path:
    """A copy of the editor folder whose page clock differs by one comment: another harness."""
    gui = tmp_path / "gui"
    gui.mkdir()
    copy_page_files(gui, (*OWN_FILES, *EDITOR_LOCK_FILES))
    link_installed_packages(gui)
    (gui / "clock.js").write_text((gui / "clock.js").read_text() + "\n// changed\n")
    return gui


@pytest.mark.slow
def test_results_of_another_harness_are_refused_then_set_aside(
    tmp_path: Path, drivers: list[Driver], monkeypatch: pytest.MonkeyPatch, shared_ray: int
) -> None:
    """The runs under the "upgraded" editor are processes of their own: a process computes its harness once."""
    config = write_config(tmp_path, tasks={"ids": TASKS[:2]}, episodes={"synthetic": {"duration_s": 0}})
    run_dir = tmp_path / "run"
    assert run_here(config)[0] == 0
    before = {row.job_id for row in RunStore(run_dir).job_rows()}

    monkeypatch.setenv("SCRATCHWORLD_GUI_DIR", str(edited_editor(tmp_path)))  # the "upgraded" checkout
    code, out = run(drivers, config)
    assert code == 2, out
    assert "holds results of another sweep" in out and "harness fingerprint" in out
    assert "scratch-gui/clock.js" in out and "workers/" not in out  # names exactly the file that changed
    assert "Traceback" not in out

    code, out = run(drivers, config, "--force")
    assert code == 0, out
    rows = RunStore(run_dir).job_rows()
    after = {row.job_id for row in rows} - before
    assert len(before) == len(after) == 2  # every job is new under the new harness: nothing reused
    manifest = read_manifest(run_dir)
    assert manifest is not None and manifest.harness is not None
    assert {row.harness_fingerprint for row in rows if row.job_id in after} == {manifest.harness.digest}
    loaded = load_run(run_dir)
    assert {row.job_id for row in loaded.rows} == after and loaded.stale_rows == 2

    monkeypatch.delenv("SCRATCHWORLD_GUI_DIR")
    other = write_config(
        tmp_path, tasks={"ids": TASKS[:2]}, episodes={"synthetic": {"duration_s": 0}}, output=str(tmp_path / "b")
    )
    assert run_here(other)[0] == 0
    report = invoke("report", str(run_dir), str(tmp_path / "b"))
    assert report.returncode == 2
    assert "differ in harness" in report.stderr and "scratch-gui/clock.js" in report.stderr


@pytest.mark.parametrize("listener", ["refusing", "silent"])
def test_a_cluster_that_cannot_be_joined_fails_fast_naming_it(tmp_path: Path, listener: str) -> None:
    with socket.socket() as silent:  # accepts connections (the kernel does) but never speaks Ray
        silent.bind(("0.0.0.0", 0))
        silent.listen()
        address = "127.0.0.1:9" if listener == "refusing" else f"127.0.0.1:{silent.getsockname()[1]}"
        config = write_config(tmp_path, ray={"address": address, "connect_timeout_s": 3}, episodes={"synthetic": {}})
        # A hang detector: Ray's own retries take minutes; the probe's 3 s (named below) ended this one.
        done = subprocess.run([SCRATCHWORLD, "run", str(config)], capture_output=True, text=True, timeout=120)
    assert done.returncode == 2, done.stderr
    lines = done.stderr.strip().splitlines()
    assert lines[-1].startswith("error: ") and address in lines[-1]
    assert ("cannot reach" if listener == "refusing" else "does not answer as a Ray cluster within 3 s") in lines[-1]
    assert "Traceback" not in done.stderr and "gcs_client" not in done.stderr and "rpc_client" not in done.stderr


# -- drivers in this process, on one Ray for the module (they are neither killed nor signalled) ---------


@pytest.mark.parametrize("output", ["/proc/scratchworld-run", "a-file/run"])
def test_an_unwritable_output_is_one_line_naming_it(tmp_path: Path, output: str) -> None:
    (tmp_path / "a-file").write_text("not a folder")
    target = output if output.startswith("/") else str(tmp_path / output)
    config = write_config(tmp_path, output=target, episodes={"synthetic": {}})
    done = invoke("run", str(config))
    assert done.returncode == 2
    last = done.stderr.strip().splitlines()[-1]
    assert last.startswith(f"error: {target}: cannot write results here: "), done.stderr
    assert "Traceback" not in done.stderr


@pytest.mark.parametrize(
    ("fields", "message"),
    [
        ({"agent": "wizard"}, "agent"),
        ({"seeds": 0}, "seeds"),
        ({"limits": {"episode_timeout_s": -1}}, "limits.episode_timeout_s"),
        ({"models": [{"model": "openai/x", "params": {"api_key": "sk-live"}}]}, "api_key may not appear"),
        ({"tasks": {"ids": ["no_such_task"]}}, "no_such_task"),
    ],
)
def test_config_errors_are_one_line_and_start_nothing(tmp_path: Path, fields: dict, message: str) -> None:
    config = write_config(tmp_path, **fields)
    done = invoke("run", str(config))
    assert done.returncode == 2
    assert done.stderr.startswith("error: ")
    assert message in done.stderr
    assert "Traceback" not in done.stderr
    assert "sk-live" not in done.stderr
    assert not (tmp_path / "run").exists()


def test_episode_timeout_is_recorded_retried_and_kept_out_of_verdicts(tmp_path: Path, shared_ray: int) -> None:
    config = write_config(
        tmp_path,
        tasks={"ids": TASKS[:2]},
        episodes={"synthetic": {"duration_s": 60}},
        limits={"episode_timeout_s": 1, "retries": 1},
    )
    code, out = run_here(config)
    assert code == 1, out  # jobs left without a verdict
    rows = RunStore(tmp_path / "run").job_rows()
    assert sorted((row.task_id, row.attempt) for row in rows) == [
        ("bouncing_ball_stuck", 1),
        ("bouncing_ball_stuck", 2),
        ("sum_two_numbers", 1),
        ("sum_two_numbers", 2),
    ]
    assert {(row.outcome, row.error_class, row.psr) for row in rows} == {("error", "episode_timeout", None)}
    assert all(row.started_at.year > 2000 for row in rows)  # the timeout, named above, cut the 60 s episodes

    status = invoke("status", str(tmp_path / "run"))
    assert status.returncode == 0
    text = " ".join(status.stdout.split())
    assert "0/2 decided" in text
    assert "episode_timeout 2" in text


@pytest.mark.parametrize(
    ("max_steps", "order"),
    [
        ({"composite": 30, "primitive": 20}, ["primitive"] * 4 + ["composite"] * 4),
        ({"composite": 50, "primitive": 20}, ["composite"] * 4 + ["primitive"] * 4),
    ],
)
def test_the_longest_jobs_start_first(tmp_path: Path, shared_ray: int, max_steps: dict, order: list[str]) -> None:
    """A primitive step counts as two composite ones: a sweep's tail is its shortest jobs, whatever the config's
    order of modes."""
    config = write_config(
        tmp_path,
        tasks={"ids": TASKS[:2]},
        seeds=2,
        episodes={"modes": ["composite", "primitive"], "max_steps": max_steps, "synthetic": {"duration_s": 0}},
        limits={"max_in_flight": 1},
    )
    code, out = run_here(config)
    assert code == 0, out
    events = [json.loads(line) for line in (tmp_path / "run" / "events.jsonl").read_text().splitlines()]
    started = [event["mode"] for event in events if event["event"] == "job_start"]
    assert started == order
    tasks = [event["task_id"] for event in events if event["event"] == "job_start"][:4]
    assert set(tasks) == set(TASKS[:2]) and tasks[:2] == tasks[2:]  # plan order among equals: seed, then suite order


@pytest.mark.browser
@pytest.mark.slow
def test_real_episodes_in_the_browser_mixed_with_synthetic_ones(tmp_path: Path, shared_ray: int) -> None:
    """Oracle episodes in Chromium beside synthetic ones in one sweep, then the noop agent.

    (Once two tests, real episodes alone and a mixed sweep: one sweep runs the same episodes.)
    """
    synthetic = {"tasks": ["quiz_score", "star_shower"], "fail_tasks": ["quiz_score"]}
    oracle = write_config(
        tmp_path, tasks={"ids": TASKS}, episodes={"synthetic": synthetic}, seeds=2, limits={"episode_timeout_s": 240}
    )
    code, out = run_here(oracle)
    assert code == 0, out
    rows = RunStore(tmp_path / "run").job_rows()
    real = [row for row in rows if row.task_id not in synthetic["tasks"]]
    assert sorted((row.task_id, row.outcome) for row in real) == [
        ("bouncing_ball_stuck", "passed"),
        ("bouncing_ball_stuck", "passed"),
        ("sum_two_numbers", "passed"),
        ("sum_two_numbers", "passed"),
    ]
    suite = load_suite(REPO / "tasks")
    for row in real:
        assert row.tests_passed == row.tests_total >= 3
        trajectory = suite.task(row.task_id).trajectory()
        expected = len(trajectory) + 1 if trajectory is not None else 2  # replayed actions (or a load), then done
        assert row.steps == expected
        artifacts = tmp_path / "run" / str(row.artifact_dir)
        assert (artifacts / "final.sb3").read_bytes()[:2] == b"PK"
        assert len((artifacts / "trajectory.jsonl").read_text().splitlines()) == expected
    assert sorted(
        (row.task_id, row.steps, row.tests_total) for row in real if row.task_id == "bouncing_ball_stuck"
    ) == [
        ("bouncing_ball_stuck", 3, 4),  # the oracle's two actions, then done; the task's own tests
        ("bouncing_ball_stuck", 3, 4),
    ]
    assert sorted((row.task_id, row.outcome, row.steps, row.tests_total) for row in rows if row not in real) == [
        ("quiz_score", "failed", 1, 2),  # synthetic: one step, two tests
        ("quiz_score", "failed", 1, 2),
        ("star_shower", "passed", 1, 2),
        ("star_shower", "passed", 1, 2),
    ]
    assert {row.eval_profile for row in real} == {"native"}  # evaluated in an editor
    assert {row.eval_profile for row in rows if row not in real} == {None}
    tests = RunStore(tmp_path / "run").read_table("tests")
    assert tests.num_rows == sum(row.tests_total for row in rows)

    noop = write_config(tmp_path, agent="noop", tasks={"ids": ["bouncing_ball_stuck"]}, output=str(tmp_path / "noop"))
    code, out = run_here(noop)
    assert code == 0, out
    (row,) = RunStore(tmp_path / "noop").job_rows()
    assert row.outcome == "failed"  # a debug task's initial project must fail
    assert row.tests_passed < row.tests_total
    assert row.stop_reason == "done"


def test_a_run_dir_of_another_sweep_is_refused(tmp_path: Path, shared_ray: int) -> None:
    config = write_config(tmp_path, tasks={"ids": TASKS[:1]}, episodes={"synthetic": {"duration_s": 0}})
    assert run_here(config)[0] == 0
    changed = write_config(tmp_path, tasks={"ids": TASKS[:1]}, seeds=2, episodes={"synthetic": {"duration_s": 0}})
    code, out = run_here(changed)
    assert code == 2
    assert "holds results of another sweep" in out
    assert "--force" in out
    code, out = run_here(changed, "--force")
    assert code == 0, out
    assert len(RunStore(tmp_path / "run").job_rows()) == 2
