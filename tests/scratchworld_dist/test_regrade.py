"""`scratchworld regrade` end to end: a real oracle sweep in Chromium on a local Ray, regraded.

One source run serves the module (three tasks for real, two seeds; a fourth task synthetic, so its
jobs store no project and must be skipped). Regrades run in this process on the module's Ray.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
import yaml

from scratchworld_dist.results import JobRow, RunStore, effective_rows, read_manifest
from tests.conftest import REPO
from tests.support.cli_runner import invoke
from tests.support.run_dirs import job, make_run
from tests.support.sweep_driver import run_here
from workers.contract import evaluation_seed

REAL = ["sum_two_numbers", "bouncing_ball_stuck", "quiz_score"]
SYNTHETIC = "star_shower"
SEEDS = 2


@pytest.fixture(scope="module")
def source(tmp_path_factory: pytest.TempPathFactory, shared_ray: int) -> Path:
    """An oracle sweep in composite mode: 6 real jobs (virtual evaluation clock) and 2 synthetic ones."""
    folder = tmp_path_factory.mktemp("source")
    config = {
        "name": "source",
        "suite": str(REPO / "tasks"),
        "agent": "oracle",
        "seeds": SEEDS,
        "tasks": {"ids": [*REAL, SYNTHETIC]},
        "episodes": {"modes": ["composite"], "synthetic": {"tasks": [SYNTHETIC]}},
        "limits": {"episode_timeout_s": 240, "pages_per_worker": 1},
        "output": str(folder / "run"),
    }
    (folder / "sweep.yaml").write_text(yaml.safe_dump(config))
    code, out = run_here(folder / "sweep.yaml")
    assert code == 0, out
    return folder / "run"


def regrade(*args: str) -> tuple[int, str]:
    done = invoke("regrade", *args)
    return done.returncode, done.stdout + done.stderr


def by_source(run_dir: Path) -> dict[str, JobRow]:
    """A regrade's effective rows by the source job each regrades."""
    rows = effective_rows(RunStore(run_dir).job_rows())
    return {row.regraded_from: row for row in rows if row.regraded_from is not None}


def source_rows(run_dir: Path) -> dict[str, JobRow]:
    return {row.job_id: row for row in effective_rows(RunStore(run_dir).job_rows())}


@pytest.mark.browser
@pytest.mark.slow
def test_a_real_clock_regrade_keeps_every_verdict_and_resumes(source: Path, tmp_path: Path) -> None:
    out = tmp_path / "real"
    code, text = regrade(str(source), "--out", str(out), "--clock", "real")
    assert code == 0, text
    flat = " ".join(text.split())
    assert "verdicts: 6 unchanged, 0 changed" in flat
    assert f"skipped 2 job(s) that stored no final project: {SYNTHETIC} seed 0 composite" in flat

    before, after = source_rows(source), by_source(out)
    real = {job_id: row for job_id, row in before.items() if row.task_id in REAL}
    assert after.keys() == real.keys()  # the synthetic jobs stored no project: no row
    for job_id, row in after.items():
        old = before[job_id]
        assert (row.outcome, row.tests_passed, row.tests_total) == (old.outcome, old.tests_passed, old.tests_total)
        assert (old.eval_clock, row.eval_clock, row.eval_profile) == ("virtual", "real", "native")
        # Judged again under the random numbers the episode was judged under: its task's, at its sweep seed.
        assert row.eval_seed == old.eval_seed == evaluation_seed(old.task_id, old.seed)
        assert row.job_id != job_id
        assert row.task_hash != old.task_hash  # the clock is part of the task's content hash
        agent_side = ("model", "agent", "mode", "task_id", "category", "seed", "steps", "stop_reason", "agent_s")
        assert [getattr(row, c) for c in agent_side] == [getattr(old, c) for c in agent_side]
        assert row.worker_pid is not None
        folder = out / str(row.artifact_dir)
        assert (folder / "final.sb3").read_bytes() == (source / str(old.artifact_dir) / "final.sb3").read_bytes()
        assert len((folder / "trajectory.jsonl").read_text().splitlines()) == row.steps
    store = RunStore(out)
    assert store.read_table("steps").num_rows == sum(row.steps for row in after.values())
    assert store.read_table("tests").num_rows == sum(row.tests_total for row in after.values())

    manifest = read_manifest(out)
    assert manifest is not None
    info = manifest.regrade
    assert info is not None
    assert (info.source_run, info.source_run_name) == (str(source.resolve()), "source")
    assert (info.profile, info.clock, info.regraded_jobs, info.without_project) == ("native", "real", 6, 2)
    assert info.suite.root == str(REPO / "tasks")
    assert manifest.suite.hash == info.suite.hash
    assert (out / "report.md").is_file()
    assert invoke("status", str(out)).returncode == 0
    assert invoke("report", str(out)).returncode == 0

    code, text = regrade(str(source), "--out", str(out), "--clock", "real")  # nothing left to do
    assert code == 0, text
    assert "6 already decided, 0 to run" in " ".join(text.split())
    assert "sent 0 attempt(s)" in " ".join(text.split())
    assert len(store.job_rows()) == 6

    code, text = regrade(str(source), "--out", str(out))  # the source's clock: another regrade
    assert code == 2
    assert "holds results of another run" in text
    assert "--force" in text


@pytest.mark.browser
@pytest.mark.slow
def test_a_changed_evaluation_script_flips_exactly_its_tasks_verdicts(source: Path, tmp_path: Path) -> None:
    suite = tmp_path / "tasks"
    shutil.copytree(REPO / "tasks", suite, ignore=shutil.ignore_patterns("__pycache__"))
    script = suite / "compute" / "sum_two_numbers" / "evaluate.js"
    text = script.read_text()
    assert "[[3, 4], 7]" in text
    script.write_text(text.replace("[[3, 4], 7]", "[[3, 4], 8]"))  # the golden solution says 7: one test fails

    out = tmp_path / "fixed"
    code, text = regrade(str(source), "--out", str(out), "--suite", str(suite))
    assert code == 0, text
    flat = " ".join(text.split())
    assert "verdicts: 4 unchanged, 2 changed" in flat
    for seed in range(SEEDS):
        assert f"sum_two_numbers seed {seed} composite: passed -> failed (tests 3/3 -> 2/3)" in flat

    before, after = source_rows(source), by_source(out)
    flipped = {job_id for job_id, row in after.items() if row.outcome != before[job_id].outcome}
    assert flipped == {job_id for job_id, row in after.items() if row.task_id == "sum_two_numbers"}
    assert len(flipped) == SEEDS
    assert {after[job_id].outcome for job_id in flipped} == {"failed"}
    assert {row.eval_clock for row in after.values()} == {"virtual"}  # the source's clock
    failing = RunStore(out).read_table("tests").to_pylist()
    assert sorted({t["name"] for t in failing if not t["passed"]}) == ["3 + 4 = 8"]

    done = invoke("compare", str(source), str(out), "--format", "json")
    assert done.returncode == 0, done.stderr
    comparison = json.loads(done.stdout)
    note = comparison["regrade"]
    assert note["regrading"] == "b"
    assert note["unchanged"] == 4
    changes = sorted((c["task_id"], c["seed"], c["before"], c["after"], c["tests_after"]) for c in note["changed"])
    assert changes == [("sum_two_numbers", seed, "passed", "failed", "2/3") for seed in range(SEEDS)]
    markdown = invoke("compare", str(out), str(source)).stdout  # either order: the manifest says which is which
    assert "A regrades B" in markdown
    assert "clock virtual" in markdown
    assert markdown.count("passed -> failed") == SEEDS


def assert_one_line_errors(cases: list[tuple[tuple[str, ...], str]]) -> None:
    for args, message in cases:
        code, text = regrade(*args)
        lines = text.strip().splitlines()
        assert code == 2, (args, text)
        assert len(lines) == 1, (args, text)
        assert lines[0].startswith("error: ")
        assert message in lines[0], (args, text)


def test_what_is_no_run_to_regrade_is_one_line(tmp_path: Path) -> None:
    empty = tmp_path / "empty"
    empty.mkdir()
    drag = make_run(tmp_path / "drag", [job("d1", setting="baseline")], planned=1, tasks=1)
    bare = make_run(tmp_path / "bare", [job("j1"), job("j2", "error")], planned=2, tasks=2)  # no artifacts
    (tmp_path / "secret").mkdir()
    (tmp_path / "secret" / "final.sb3").write_bytes(b"not theirs")
    escaping = make_run(tmp_path / "escaping", [job("j1", artifact_dir="../secret")], planned=1, tasks=1)
    assert_one_line_errors(
        [
            ((str(tmp_path / "nowhere"), "--out", str(tmp_path / "a")), "not a scratchworld run directory"),
            ((str(empty), "--out", str(tmp_path / "a")), "not a scratchworld run directory (no manifest.json in it)"),
            ((str(drag), "--out", str(tmp_path / "a")), "a drag benchmark run stores drags"),
            ((str(drag), "--out", str(drag)), "--out is the source run itself"),
            ((str(bare), "--out", str(tmp_path / "a")), "none of its 2 job(s) stored a final project"),
            ((str(escaping), "--out", str(tmp_path / "a")), "names artifacts outside the run (../secret)"),
        ]
    )
    assert not (tmp_path / "a").exists()


@pytest.mark.browser
def test_bad_conditions_are_one_line_and_write_nothing(source: Path, tmp_path: Path) -> None:
    lacking = tmp_path / "lacking"
    shutil.copytree(REPO / "tasks", lacking, ignore=shutil.ignore_patterns("__pycache__"))
    shutil.rmtree(lacking / "extend" / "quiz_score")
    out = str(tmp_path / "a")
    assert_one_line_errors(
        [
            ((str(source), "--out", str(source)), "--out is the source run itself"),
            ((str(source), "--out", out, "--profile", "wide"), "'wide' is not one of"),
            ((str(source), "--out", out, "--clock", "sundial"), "'sundial' is not one of"),
            ((str(source), "--out", out, "--suite", str(lacking)), "lacks task(s) of"),
        ]
    )
    assert "quiz_score" in regrade(str(source), "--out", out, "--suite", str(lacking))[1]
    assert not (tmp_path / "a").exists()
    assert len(RunStore(source).job_rows()) == SEEDS * 4
