"""``scratchworld flakes`` as a user runs it: a phase-sensitive script is caught, a stable one is not.

The suites are written by ``tests/support/flaky_suite.py`` with the sb3 builder; ``--axes`` and ``--runs``
keep each run to a few dozen evaluations.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

import pytest

from tests.conftest import REPO
from tests.support.cli_runner import Done, invoke
from tests.support.flaky_suite import write_flaky_suite

pytestmark = pytest.mark.browser

TEST_KEYS = {
    "task_id",
    "category",
    "which",
    "test",
    "stable",
    "baseline",
    "runs",
    "flipped",
    "rate",
    "rate_by_axis",
    "flips",
    "lateness_band",
    "blocking",
}
RUN_KEYS = {"task_id", "category", "which", "variant", "verdicts", "error", "load_average", "wall_s"}


@pytest.fixture
def run(monkeypatch: pytest.MonkeyPatch) -> Callable[..., Done]:
    monkeypatch.chdir(REPO)
    return invoke


@pytest.fixture
def flaky_suite(tmp_path: Path) -> Path:
    return write_flaky_suite(tmp_path / "flaky")


def test_a_phase_sensitive_golden_is_caught_with_the_phase_that_flips_it(
    tmp_path: Path, flaky_suite: Path, run: Callable[..., Done]
) -> None:
    out = tmp_path / "flakes.json"
    stability = flaky_suite / "stability.json"
    done = run(
        "flakes", str(flaky_suite), "--tasks", "phase_sensitive", "--axes", "phase,lateness", "--json", str(out),
        "--stability-out", str(stability),
    )  # fmt: skip
    assert done.returncode == 1, done.stdout + done.stderr
    assert "1 in goldens or debug initials" in " ".join(done.stderr.split())
    report = json.loads(out.read_text())
    golden = next(row for row in report["tests"] if row["which"] == "golden")
    assert golden["stable"] is False and golden["blocking"] is True and golden["baseline"] == "pass"
    # Phases 8.2, 16.5 and 24.8 ms: only the last leaves one frame in 50 ms.
    assert [(flip["axis"], flip["label"], flip["verdict"]) for flip in golden["flips"] if flip["axis"] == "phase"] == [
        ("phase", "phase 24.8 ms", "fail")
    ]
    assert golden["rate_by_axis"]["phase"] == pytest.approx(1 / 3, abs=0.001)
    # Lateness stretches the frame interval: a second frame within 50 ms needs 33 + L <= 50.
    band = golden["lateness_band"]
    assert band["passes_ms"] == [0, 4, 8, 15] and band["fails_ms"] == [25]
    assert band["min_fps"] == pytest.approx(20.8) and band["max_fps"] == pytest.approx(30.3)
    initial = next(row for row in report["tests"] if row["which"] == "initial")
    assert initial["stable"] is True and initial["baseline"] == "fail"
    assert "unstable: phase_sensitive golden" in done.stdout and "phase 24.8 ms → fail" in done.stdout

    # The findings are the suite's known stability now: validate marks the test, says what flips it, where
    # it passes, and which tasks the flake run did not check.
    checked = run("validate", str(flaky_suite))
    text = " ".join(checked.stdout.split())
    assert "phase_sensitive ~" in text, checked.stdout
    assert "~ phase_sensitive" in text and "unstable: phase, lateness changed it in 2 of" in text
    assert "passes at golden 20.8-30.3 fps (fails at 25 ms)" in text
    assert "not checked or changed since: steady" in text


def test_a_stable_suite_is_reported_stable_with_every_perturbation_recorded(
    tmp_path: Path, flaky_suite: Path, run: Callable[..., Done]
) -> None:
    out = tmp_path / "flakes.json"
    done = run(
        "flakes", str(flaky_suite), "--tasks", "steady", "--runs", "1", "--lateness", "0,25",
        "--load-processes", "1", "--json", str(out),
    )  # fmt: skip
    assert done.returncode == 0, done.stdout + done.stderr
    assert "0 of 4 test(s) unstable" in " ".join(done.stderr.split())
    report = json.loads(out.read_text())
    assert set(report) == {
        "suite", "conditions", "settings", "evaluations", "unstable", "blocking", "tests", "runs"
    }  # fmt: skip
    assert report["conditions"] == {"profile": "native", "clock": "virtual", "render": "on_demand", "page": "bare"}
    assert report["settings"]["axes"] == ["seed", "phase", "mouse", "lateness", "clock", "render", "load"]
    # baseline + seed, phase, mouse, 2 lateness levels, calibrated timing, clock, render, load: 10 runs each.
    assert report["evaluations"] == 20 == len(report["runs"])
    assert (report["unstable"], report["blocking"]) == (0, 0)
    for row in report["tests"]:
        assert set(row) == TEST_KEYS and row["stable"] and row["flips"] == [] and row["runs"] == 10
    golden_draw = next(r for r in report["tests"] if r["which"] == "golden" and r["test"] == "a draw from 1 to 10")
    assert golden_draw["lateness_band"]["passes_ms"] == [0, 25]
    runs = report["runs"]
    for record in runs:
        assert set(record) == RUN_KEYS and record["error"] is None
        assert set(record["variant"]) == {"axis", "label", "clock", "render", "perturbation", "timing", "cpu_load"}
        assert isinstance(record["variant"]["perturbation"]["random_seed"], int)
    by_axis = {record["variant"]["axis"]: record["variant"] for record in runs if record["which"] == "golden"}
    assert by_axis["clock"]["clock"] == "real" and by_axis["render"]["render"] == "every_frame"
    assert by_axis["load"]["cpu_load"] == 1 and by_axis["mouse"]["perturbation"]["mouse"] is not None
    assert by_axis["seed"]["perturbation"]["random_seed"] != by_axis["baseline"]["perturbation"]["random_seed"]


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (("--axes", "phase,wind"), "wind; choose from seed, phase"),
        (("--lateness", "4,x"), "is not a comma-separated list of milliseconds"),
        (("--runs", "0"), "--runs"),
    ],
)
def test_bad_options_get_a_one_line_error_and_exit_2(
    flaky_suite: Path, run: Callable[..., Done], args: tuple[str, ...], message: str
) -> None:
    done = run("flakes", str(flaky_suite), *args)
    assert done.returncode == 2
    assert message in done.stderr and done.stderr.count("\n") == 1, done.stderr


def test_an_upstream_clone_runs_and_reports_its_tests(
    tmp_path: Path, fake_clone: Path, run: Callable[..., Done]
) -> None:
    """A clone in upstream's layout (tests/support/fake_clone.py) runs under upstream's conditions."""
    out = tmp_path / "flakes.json"
    done = run(
        "flakes", str(fake_clone), "--tasks", "sum_two", "--axes", "seed,phase", "--runs", "1", "--json", str(out),
    )  # fmt: skip
    assert done.returncode in (0, 1), done.stdout + done.stderr
    report = json.loads(out.read_text())
    assert report["conditions"]["profile"] == "upstream" and report["conditions"]["clock"] == "virtual"
    assert {row["task_id"] for row in report["tests"]} == {"sum_two"} and len(report["runs"]) == 6
