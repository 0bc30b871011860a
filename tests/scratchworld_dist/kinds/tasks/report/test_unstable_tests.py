"""Known test stability in reports and comparisons: the report names the tasks with unstable tests and the
failed verdicts resting on them alone; ``compare --stable-only`` judges jobs without those tests; runs
without stability data, and comparisons without the flag, print as they did."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from scratchworld_dist.kinds.tasks.report import build_report, render_markdown
from scratchworld_dist.kinds.tasks.report._stable_only import left_out_tests, stable_verdicts
from scratchworld_dist.reports._runs import load_run
from tests.support.cli_runner import invoke
from tests.support.run_dirs import job, job_with_tests, make_run
from tests.support.unstable_runs import BEAT_NOTE, HOSTILE, HOSTILE_NOTE, MARKS, STRONG, WEAK, marked_run


def test_the_report_names_unstable_tests_once_per_task_and_counts_the_verdicts_resting_on_them(
    tmp_path: Path,
) -> None:
    run = marked_run(tmp_path / "run", WEAK, model="gpt")
    done = invoke("report", str(run))
    assert done.returncode == 0, done.stderr
    section = done.stdout.split("## Unstable tests\n\n", 1)[1].split("\n\nSR = ", 1)[0]
    paragraph, table = section.split("\n\n")
    assert "/suite/stability.json, made 2026-11-20" in paragraph
    assert "4 of 4 task(s) checked; 2 task(s) have tests" in paragraph
    # t1 seed 0 failed only 'moves on the beat'; t1 seed 1 and t3 failed stable tests too; t4 failed its only one.
    assert "2 failed job verdict(s) rest on them alone" in paragraph
    rows = table.splitlines()[2:]
    assert rows == [
        f"| t1 | 'moves on the beat' ({BEAT_NOTE}) | 2 | 2 | 1 |",
        f"| t4 | '{HOSTILE}' ({HOSTILE_NOTE}) | 1 | 1 | 1 |",
    ]
    data = json.loads(invoke("report", str(run), "--format", "json").stdout)["stability"]
    assert data["failed_on_unstable_only"] == 2 and (data["tasks"], data["checked"]) == (4, 4)
    assert data["unstable_tasks"][0] == {
        "task_id": "t1",
        "tests": {"moves on the beat": BEAT_NOTE},
        "determinate": 2,
        "failed": 2,
        "failed_on_unstable_only": 1,
    }
    html = invoke("report", str(run), "--format", "html").stdout
    assert "&lt;b&gt;only&lt;/b&gt; test" in html and "<b>only</b>" not in html


def test_a_run_without_stability_data_reports_as_before(tmp_path: Path) -> None:
    marked = build_report([marked_run(tmp_path / "a", WEAK, model="gpt")])
    plain = build_report([marked_run(tmp_path / "b", WEAK, model="gpt", marks=None)])
    assert plain.stability is None and "stability" not in json.loads(plain.model_dump_json())
    assert "Unstable" not in render_markdown(plain)
    # The section is all the marks add: the rest of the report is the same.
    without_section = render_markdown(marked.model_copy(update={"stability": None}))
    assert without_section == render_markdown(plain).replace(str(tmp_path / "b"), str(tmp_path / "a"))


def _compare(*args: str) -> str:
    done = invoke("compare", *args, "--resamples", "200")
    assert done.returncode == 0, done.stderr
    return done.stdout


def test_stable_only_recomputes_the_verdicts_that_rest_on_unstable_tests_and_says_so(tmp_path: Path) -> None:
    weak = marked_run(tmp_path / "weak", WEAK, model="gpt")
    strong = marked_run(tmp_path / "strong", STRONG, model="claude")
    recorded = json.loads(_compare(str(weak), str(strong), "--format", "json"))
    stable = json.loads(_compare(str(weak), str(strong), "--format", "json", "--stable-only"))
    assert "stable_only" not in recorded
    # Recorded: five pairs with a verdict (t3 seed 1 is an error), A passed t2 alone.
    assert (recorded["paired_jobs"], recorded["without_verdict"]) == (5, 1)
    assert recorded["sr"]["a"] == pytest.approx(1 / 5)
    # Stable only: t4 has no test left (no verdict on either side); t1 seed 0 passes now, t1 seed 1 still fails.
    assert (stable["paired_jobs"], stable["without_verdict"]) == (4, 2)
    assert (stable["sr"]["a"], stable["sr"]["b"]) == (pytest.approx(2 / 4), 1.0)
    assert stable["psr"]["a"] == pytest.approx((1 + 0 + 1 + 0) / 4)  # t1 seed 1 fails its one stable test
    tasks = {t["task_id"]: (t["a_passed"], t["jobs"]) for t in stable["per_task"]}
    assert tasks == {"t1": (1, 2), "t2": (1, 1), "t3": (0, 1)}
    assert stable["stable_only"]["left_out"] == {"t1": ["moves on the beat"], "t4": [HOSTILE]}
    sides = [(s["label"], s["changed"], s["without_test"], s["kept"]) for s in stable["stable_only"]["sides"]]
    assert sides == [("A", 1, 1, 0), ("B", 0, 1, 0)]
    text = _compare(str(weak), str(strong), "--stable-only")
    assert f"left out for both sides: t1: 'moves on the beat'; t4: '{HOSTILE}'." in text
    assert "A: 1 verdict(s) changed, 1 job(s) left with no test" in text
    assert "| SR | 50.0% | 100.0% | -50.0 pp |" in text


def test_without_the_flag_a_comparison_of_marked_runs_prints_as_one_of_unmarked_runs(tmp_path: Path) -> None:
    marked = [marked_run(tmp_path / "a", WEAK, model="gpt"), marked_run(tmp_path / "b", STRONG, model="claude")]
    plain = [
        marked_run(tmp_path / "c", WEAK, model="gpt", marks=None),
        marked_run(tmp_path / "d", STRONG, model="claude", marks=None),
    ]
    for fmt in ("md", "json"):
        ours = _compare(*map(str, marked), "--format", fmt)
        theirs = _compare(*map(str, plain), "--format", fmt)
        assert ours == theirs.replace(str(tmp_path / "c"), str(tmp_path / "a")).replace(
            str(tmp_path / "d"), str(tmp_path / "b")
        )


def test_a_ranking_leaves_the_same_tests_out_for_every_system(tmp_path: Path) -> None:
    weak = marked_run(tmp_path / "weak", WEAK, model="gpt")
    strong = marked_run(tmp_path / "strong", STRONG, model="claude")
    unmarked = marked_run(tmp_path / "unmarked", WEAK, model="llama", marks=None)
    recorded = json.loads(_compare(str(weak), str(strong), str(unmarked), "--format", "json"))
    stable = json.loads(_compare(str(weak), str(strong), str(unmarked), "--format", "json", "--stable-only"))
    assert "stable_only" not in recorded
    srs = {s["label"]: (s["determinate"], s["sr"]) for s in stable["systems"]}
    # The unmarked run's jobs are judged without the tests the others mark: its t1 seed 0 passes too.
    assert srs == {"claude": (4, 1.0), "gpt": (4, 0.5), "llama": (4, 0.5)}
    assert {s["label"]: s["sr"] for s in recorded["systems"]}["llama"] == pytest.approx(1 / 5)
    assert [(s["label"], s["changed"]) for s in stable["stable_only"]["sides"]] == [
        ("gpt", 1),
        ("claude", 0),
        ("llama", 1),
    ]
    assert stable["stable_only"]["runs_without"] == [f"sweep ({unmarked})"]
    pair = next(p for p in stable["pairs"] if (p["a"], p["b"]) == ("gpt", "claude"))
    assert (pair["paired_jobs"], pair["sr_difference"]) == (4, -0.5)
    text = _compare(str(weak), str(strong), str(unmarked), "--stable-only")
    assert "Stable tests only (--stable-only)" in text and "Runs without stability data" in text


def test_stable_only_keeps_verdicts_it_cannot_recompute(tmp_path: Path) -> None:
    """A job without test rows, and one whose project broke the evaluation script, keep what they recorded."""
    rows = [
        job("bare", "failed", task_id="t1", tests_passed=0, tests_total=2, psr=0.0),  # no test rows
        job_with_tests("broke", {"moves on the beat": False}, MARKS, task_id="t1", eval_error_kind="script_error"),
        job_with_tests("beat", {"moves on the beat": False, "score shown": True}, MARKS, task_id="t1"),
    ]
    run = load_run(make_run(tmp_path / "run", rows, planned=3, tasks=1, stability=MARKS))
    left_out = left_out_tests([run])
    assert left_out == {"t1": ["moves on the beat"], "t4": [HOSTILE]}
    recomputed, side = stable_verdicts(run, run.rows, left_out, "A")
    assert {row.job_id: row.outcome for row in recomputed} == {"bare": "failed", "broke": "failed", "beat": "passed"}
    assert (side.changed, side.without_test, side.kept) == (1, 0, 1)
