"""The command line as a user runs it, through its entry point (in this process, see ``tests/support/cli_runner.py``);
``gui``, a server that must outlive its caller, runs as a process of its own."""

from __future__ import annotations

import json
import subprocess
import sys
import urllib.request
from collections.abc import Callable
from pathlib import Path

import pytest

from scratchworld_dist.sb3 import check_project
from tests.conftest import REPO, SUITE_DIR
from tests.support.cli_runner import Done, invoke
from tests.support.retries import SecondLooks

pytestmark = pytest.mark.browser

SCRATCHWORLD = str(Path(sys.executable).with_name("scratchworld"))


@pytest.fixture
def run(monkeypatch: pytest.MonkeyPatch) -> Callable[..., Done]:
    """``scratchworld ARGS...`` from the repository, as a user in it would type it."""
    monkeypatch.chdir(REPO)
    return invoke


@pytest.mark.slow
def test_validate_our_suite_is_green_under_both_clocks(
    tmp_path: Path, run: Callable[..., Done], second_looks: SecondLooks
) -> None:
    """The main job: every golden passes, every initial falls short, JSON as documented.

    Our suite's default clock is virtual; real time must give the same verdicts, test for test, once load
    did not delay it. A real-clock verdict on a timing test depends on load (four editors on two cores, beside
    the other tests): a task whose verdicts differ is validated again alone, up to twice, and each such look
    is reported in the run's summary; more than a quarter of the tasks needing one fails the test.
    """
    verdicts: dict[str, list[tuple[object, ...]]] = {}
    for clock in ("default", "real"):
        out = tmp_path / f"validate-{clock}.json"
        # Real-clock evaluations mostly wait out their scripts' own time, so more run at once.
        choice = ["--parallel", "2"] if clock == "default" else ["--parallel", "4", "--clock", clock]
        done = run("validate", str(SUITE_DIR), *choice, "--json", str(out))
        rows = json.loads(out.read_text())
        assert len(rows) >= 12
        for row in rows:
            assert set(row) == {"task_id", "category", "golden", "initial", "unstable_tests"}
            assert set(row["golden"]) == {
                *("success", "passed", "total", "psr", "error", "wall_s", "failed_tests", "random_seed")
            }
            assert row["unstable_tests"] == {}  # tasks/stability.json checked every task: none is unstable
        if clock == "default":  # the real clock's verdicts are compared with these below
            assert done.returncode == 0, done.stdout + done.stderr
            assert "all" in done.stderr and "valid" in done.stderr
            for row in rows:
                assert row["golden"]["success"] and row["golden"]["error"] is None, row
                assert row["initial"]["psr"] < 1, row
                if row["category"] == "debug":
                    assert not row["initial"]["success"], row
        assert f"profile native, clock {'virtual' if clock == 'default' else clock}" in " ".join(done.stderr.split())
        verdicts[clock] = [
            (row["task_id"], which, *(row[which][key] for key in ("success", "passed", "total", "error")))
            for row in rows
            for which in ("golden", "initial")
        ]
    for task in sorted({row[0] for row in set(verdicts["default"]) ^ set(verdicts["real"])}):
        virtual = [v for v in verdicts["default"] if v[0] == task]
        real = [v for v in verdicts["real"] if v[0] == task]
        for look in range(2):
            second_looks.took(task, f"real {real} against virtual {virtual}")
            out = tmp_path / f"validate-real-{task}-{look}.json"
            run("validate", str(SUITE_DIR), "--tasks", task, "--clock", "real", "--json", str(out))
            real = [
                (row["task_id"], which, *(row[which][key] for key in ("success", "passed", "total", "error")))
                for row in json.loads(out.read_text())
                for which in ("golden", "initial")
            ]
            if real == virtual:
                break
        verdicts["real"] = [v for v in verdicts["real"] if v[0] != task] + real
    assert sorted(verdicts["default"]) == sorted(verdicts["real"])
    tasks = len({row[0] for row in verdicts["default"]})
    second_looks.at_most(tasks // 4, tasks, "tasks")


def test_validate_exits_1_when_a_golden_fails(tmp_path: Path, run: Callable[..., Done]) -> None:
    suite = tmp_path / "suite"
    (suite / "compute").mkdir(parents=True)
    for name in ("suite.json", "harness.js"):
        (suite / name).write_bytes((SUITE_DIR / name).read_bytes())
    task = suite / "compute" / "swapped"
    task.mkdir()
    source = SUITE_DIR / "compute" / "sum_two_numbers"
    for name in ("task.json", "evaluate.js"):
        (task / name).write_bytes((source / name).read_bytes())
    # The golden is the unsolved starter: validation must refuse the task.
    (task / "golden.sb3").write_bytes((source / "initial.sb3").read_bytes())
    (task / "initial.sb3").write_bytes((source / "initial.sb3").read_bytes())
    out = tmp_path / "v.json"
    done = run("validate", str(suite), "--json", str(out))
    assert done.returncode == 1, done.stdout + done.stderr
    assert "golden does not pass" in done.stdout
    assert json.loads(out.read_text())[0]["golden"]["success"] is False


def test_evaluate_exit_codes_and_json(tmp_path: Path, run: Callable[..., Done]) -> None:
    task = SUITE_DIR / "compute" / "sum_two_numbers"
    out = tmp_path / "result.json"
    golden = run("evaluate", str(SUITE_DIR), "sum_two_numbers", str(task / "golden.sb3"), "--json", str(out))
    assert golden.returncode == 0, golden.stderr
    assert json.loads(out.read_text())["passed"] == 3
    initial = run("evaluate", str(SUITE_DIR), "sum_two_numbers", str(task / "initial.sb3"))
    assert initial.returncode == 1
    corrupt = tmp_path / "corrupt.sb3"
    corrupt.write_bytes(b"PK\x03\x04 not really")
    broken = run("evaluate", str(SUITE_DIR), "sum_two_numbers", str(corrupt))
    assert broken.returncode == 3
    assert "project_invalid" in broken.stdout


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (("validate", "/nonexistent/suite"), "error: /nonexistent/suite: no such directory"),
        (("validate", str(SUITE_DIR), "--tasks", "nope"), "error: no task 'nope'"),
        (("evaluate", str(SUITE_DIR), "nope", str(SUITE_DIR / "suite.json")), "error: no task 'nope'"),
    ],
)
def test_user_errors_are_one_line(args: tuple[str, ...], message: str, run: Callable[..., Done]) -> None:
    done = run(*args)
    assert done.returncode == 2
    assert done.stderr.startswith(message)
    assert "Traceback" not in done.stderr


def test_gui_serves_the_editor_on_loopback() -> None:
    with subprocess.Popen([SCRATCHWORLD, "gui", "--port", "0"], stdout=subprocess.PIPE, text=True, cwd=REPO) as process:
        try:
            assert process.stdout is not None
            line = process.stdout.readline()
            url = line.rsplit(" at ", 1)[1].strip()
            assert url.startswith("http://127.0.0.1:")
            with urllib.request.urlopen(url, timeout=10) as response:
                assert b"scratchworld.attachVm" in response.read()
        finally:
            process.terminate()


def test_committed_projects_are_what_their_sources_build() -> None:
    done = subprocess.run(
        [sys.executable, str(SUITE_DIR / "build_projects.py"), "--check"], capture_output=True, text=True, cwd=REPO
    )
    assert done.returncode == 0, done.stdout
    for golden in SUITE_DIR.glob("*/*/golden.sb3"):
        check_project(golden.read_bytes())


@pytest.mark.slow
def test_replay_golden_and_custom_trajectories(tmp_path: Path, run: Callable[..., Done]) -> None:
    out = tmp_path / "replay.json"
    saved = tmp_path / "fixed.sb3"
    done = run("replay", str(SUITE_DIR), "bouncing_ball_stuck", "--json", str(out), "--save", str(saved), "--observe")
    assert done.returncode == 0, done.stdout + done.stderr
    assert "#6 motion_ifonedgebounce" in done.stdout  # the final observation
    report = json.loads(out.read_text())
    assert report["task_id"] == "bouncing_ball_stuck"
    assert [step["success"] for step in report["steps"]] == [True, True]
    assert report["eval"]["success"] is True
    assert report["eval"]["passed"] == report["eval"]["total"] >= 3
    assert check_project(saved.read_bytes())["targets"][1]["name"] == "Ball"

    # A trajectory with a refused action and no fix: the envelope shows the code, the task fails.
    wrong = tmp_path / "wrong.json"
    wrong.write_text(
        json.dumps(
            [{"api": "select_sprite", "args": {"name": "Bal'l"}}, {"api": "delete_block", "args": {"blockIndex": 9}}]
        )
    )
    failed = run("replay", str(SUITE_DIR), "bouncing_ball_stuck", str(wrong))
    assert failed.returncode == 1
    assert "NOT_FOUND" in failed.stdout

    malformed = tmp_path / "malformed.json"
    malformed.write_text('{"api": "done"}')
    refused = run("replay", str(SUITE_DIR), "bouncing_ball_stuck", str(malformed))
    assert refused.returncode == 2
    assert refused.stderr.startswith("error: ")
    assert "malformed.json" in refused.stderr
