"""The drag benchmark's report: Pass@k two ways, start/end accuracy, distances, and ``scratchworld report``."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest
from click.testing import CliRunner

from scratchworld_dist._errors import RunDirError
from scratchworld_dist.cli._main import cli
from scratchworld_dist.kinds.drag._metrics import DragRun, DragTable, drag_cell, drag_rows, join_runs
from scratchworld_dist.kinds.drag._table import build_drag_report, is_drag_run, render_drag_markdown
from scratchworld_dist.results import JobRecord
from tests.support.run_dirs import HARNESS, make_run
from tests.support.run_dirs import drag_job as job
from tests.support.run_dirs import drag_row as drag_of


def run(task: str, seed: int, outcome: str, **drag: Any) -> DragRun:
    row = job(task, seed, outcome, **drag.pop("job", {}))
    return DragRun(job=row, drag=None if outcome == "error" else drag_of(row, **drag))


def test_unbiased_pass_at_k_and_upstream_any_of_first_k_depend_on_seed_order() -> None:
    late = drag_cell("T1", [run("a", 0, "failed"), run("a", 1, "failed"), run("a", 2, "passed")])
    early = drag_cell("T1", [run("a", 2, "failed"), run("a", 1, "failed"), run("a", 0, "passed")])
    for cell in (late, early):
        assert cell.k_max == 3
        assert [p.unbiased for p in cell.pass_at_k] == pytest.approx([1 / 3, 2 / 3, 1.0])
    assert [p.empirical for p in late.pass_at_k] == [0.0, 0.0, 1.0]
    assert [p.empirical for p in early.pass_at_k] == [1.0, 1.0, 1.0]


def test_pass_at_k_stops_at_the_fewest_runs_and_averages_over_tasks() -> None:
    runs = [run("a", s, "passed") for s in range(3)] + [run("b", 0, "failed"), run("b", 1, "passed")]
    cell = drag_cell("ALL", [*runs, run("b", 2, "error")])
    assert (cell.tasks, cell.runs, cell.error_runs, cell.k_max) == (2, 5, 1, 2)
    # a: n=3, c=3 -> 1, 1; b: n=2, c=1 -> 1/2, 1.
    assert [p.unbiased for p in cell.pass_at_k] == pytest.approx([0.75, 1.0])
    assert [p.empirical for p in cell.pass_at_k] == [0.5, 1.0]


def test_accuracies_and_distances_use_the_right_subsets() -> None:
    runs = [
        run("a", 0, "passed"),
        run("b", 0, "failed", start=0.0, end=10.0),
        run("c", 0, "failed", start=0.0, end=30.0),
        run("d", 0, "failed", start=5.0, end=100.0),  # a start miss: its end distance is not about the end
        run("e", 0, "failed", start=8.0, end=7.0),
        run("f", 0, "failed", start=50.0, end=60.0, parse="out_of_screen"),
        run("g", 0, "failed", start=None, end=None, parse="unparsed"),
        run("h", 0, "error"),
    ]
    cell = drag_cell("T1", runs)
    assert (cell.runs, cell.passed, cell.start_passes, cell.error_runs) == (7, 1, 3, 1)
    assert cell.start_accuracy == pytest.approx(3 / 7)
    assert cell.end_accuracy == pytest.approx(1 / 3)
    start = cell.start_error
    assert (start.mean, start.median, start.measured, start.misses) == (pytest.approx(21.0), 8.0, 3, 4)
    assert start.coverage == pytest.approx(0.75)
    end = cell.end_error
    assert (end.mean, end.median, end.measured, end.misses, end.coverage) == (20.0, 20.0, 2, 2, 1.0)
    assert [(p.name, p.runs) for p in cell.parse_failures] == [("out_of_screen", 1), ("unparsed", 1)]
    assert [(e.name, e.runs) for e in cell.errors] == [("RateLimitError", 1)]


def test_error_runs_are_counted_but_never_scored() -> None:
    cell = drag_cell("T2", [run("a", 0, "error"), run("a", 1, "error"), run("b", 0, "failed", start=4.0)])
    assert (cell.tasks, cell.tasks_without_runs, cell.runs, cell.error_runs) == (2, 1, 1, 2)
    assert (cell.k_max, [p.unbiased for p in cell.pass_at_k]) == (1, [0.0])
    assert (cell.start_accuracy, cell.end_accuracy, cell.start_error.mean) == (0.0, None, 4.0)
    only_errors = drag_cell("T2", [run("a", 0, "error")])
    assert (only_errors.runs, only_errors.k_max, only_errors.pass_at_k, only_errors.start_accuracy) == (0, 0, [], None)


def test_join_takes_the_effective_attempt_and_its_own_drag_row() -> None:
    first = job("a", 0, "failed")
    second = job("a", 0, "passed", attempt=2)
    later_error = job("a", 0, "error", attempt=3)
    orphan = job("b", 0, "failed")
    episode = job("c", 0, "passed", setting=None)
    lucky = job("d", 0, "passed")
    drags = [drag_of(first, start=9.0), drag_of(second), drag_of(lucky, start=3.0)]
    runs, warnings = join_runs([first, second, later_error, orphan, episode, lucky], drags)
    by_task = {r.job.task_id: r for r in runs}
    assert set(by_task) == {"a", "d"}
    assert by_task["a"].job.attempt == 2 and by_task["a"].drag == drags[1]
    assert by_task["d"].start_pass  # passed counts as a start pass, as upstream's Start Pass does
    assert warnings == [
        "1 job(s) that are not drag jobs (no setting) ignored",
        "1 drag job(s) with a verdict but no drags row for their attempt left out",
        "1 passed run(s) pressed outside the start region (counted as start passes, as upstream does)",
    ]


def test_rows_per_model_and_setting_with_a_cell_per_type_and_all() -> None:
    runs = [
        run("a", 0, "passed", job={"setting": "knowledge"}),
        run("a", 0, "failed", job={"setting": "baseline"}),
        run("b", 0, "passed", job={"setting": "baseline", "drag_type": "T2"}),
        run("a", 0, "passed", job={"setting": "gt_start"}),
    ]
    rows = drag_rows(runs)
    assert [r.setting for r in rows] == ["baseline", "gt_start", "knowledge"]
    assert [c.group for c in rows[0].cells] == ["T1", "T2", "ALL"]
    assert [rows[0].cell(g).passed for g in ("T1", "T2", "ALL")] == [0, 1, 1]
    assert (rows[1].cell("T2").tasks, rows[1].cell("T2").start_accuracy) == (0, None)


# -- run directories and the command ------------------------------------------------------


def drag_run_dir(run_dir: Path) -> Path:
    """Two T1 tasks x three seeds and one T2 task, baseline; one error run and one unparsed reply."""
    records = []
    for seed, outcome in enumerate(("failed", "failed", "passed")):
        row = job("t1a", seed, outcome)
        records.append(JobRecord(job=row, drags=[drag_of(row, start=0.0, end=None if outcome == "passed" else 12.0)]))
    for seed in range(3):
        row = job("t1b", seed, "failed")
        records.append(JobRecord(job=row, drags=[drag_of(row, start=None, end=None, parse="unparsed")]))
    for seed, outcome in enumerate(("passed", "failed", "error")):
        row = job("t2a", seed, outcome, drag_type="T2")
        records.append(JobRecord(job=row, drags=[] if outcome == "error" else [drag_of(row, start=6.0 * seed)]))
    return write_run(run_dir, records)


def write_run(run_dir: Path, records: list[JobRecord]) -> Path:
    """A real run directory of a drag sweep: the records committed through ``RunStore`` and a manifest."""
    config = {"benchmark": "drag", "seeds": [0, 1, 2]}
    return make_run(run_dir, records, planned=9, tasks=3, config=config, harness=HARNESS, name="drag")


def test_report_from_a_run_directory(tmp_path: Path) -> None:
    table = build_drag_report([drag_run_dir(tmp_path / "run")])
    (row,) = table.rows
    t1, t2, every = row.cell("T1"), row.cell("T2"), row.cell("ALL")
    assert (t1.runs, t1.passed, t1.k_max, t2.runs, t2.error_runs, t2.k_max) == (6, 1, 3, 2, 1, 2)
    assert [p.unbiased for p in t1.pass_at_k] == pytest.approx([1 / 6, 1 / 3, 1 / 2])
    assert [p.empirical for p in t1.pass_at_k] == [0.0, 0.0, 0.5]
    assert (every.k_max, every.start_passes, every.runs) == (2, 4, 8)
    assert (t1.start_error.misses, t1.start_error.coverage, t1.start_error.mean) == (3, 0.0, None)
    assert (t1.end_error.mean, t1.end_error.measured, t2.start_error.mean) == (12.0, 2, 6.0)
    markdown = render_drag_markdown(table)
    assert "| model | setting | T1 Pass@1 | T1 Pass@2 | T1 Pass@3 | T1 Start acc. |" in markdown
    assert "| gpt | baseline | 16.7% | 33.3% | 50.0% | 50.0% (3/6) | 33.3% (1/3) | - | 12.0 |" in markdown
    assert "1 error runs (RateLimitError 1); parse failures: unparsed 3" in markdown


def test_cli_renders_the_drag_table_for_a_drag_run(tmp_path: Path) -> None:
    run_dir = drag_run_dir(tmp_path / "run")
    assert is_drag_run(run_dir)
    md = CliRunner().invoke(cli, ["report", str(run_dir)])
    assert md.exit_code == 0, md.output
    assert md.stdout.startswith("# ScratchWorld single-step drag report") and "## Table 2" in md.stdout
    as_json = CliRunner().invoke(cli, ["report", str(run_dir), "--format", "json"])
    assert as_json.exit_code == 0, as_json.output
    table = DragTable.model_validate(json.loads(as_json.stdout))
    assert table.rows[0].cell("ALL").passed == 2
    out = tmp_path / "drag.html"
    page = CliRunner().invoke(cli, ["report", str(run_dir), "--format", "html", "--out", str(out)])
    assert page.exit_code == 0, page.output
    text = out.read_text(encoding="utf-8")
    assert text.startswith("<!DOCTYPE html>") and "<pre># ScratchWorld single-step drag report" in text


def test_a_run_without_drag_jobs_is_not_a_drag_run(tmp_path: Path) -> None:
    episodes = write_run(tmp_path / "episodes", [JobRecord(job=job("x", 0, "passed", setting=None))])
    assert not is_drag_run(episodes) and not is_drag_run(tmp_path / "nowhere")
    with pytest.raises(RunDirError, match="no drag job results"):
        build_drag_report([episodes])
    assert CliRunner().invoke(cli, ["report", str(episodes)]).stdout.startswith("# ScratchWorld report\n")


def test_a_drag_run_whose_every_job_failed_to_run_is_still_one(tmp_path: Path) -> None:
    run_dir = write_run(tmp_path / "run", [JobRecord(job=job(t, 0, "error")) for t in ("a", "b")])
    assert is_drag_run(run_dir)  # no drags rows: the jobs' settings say so
    (row,) = build_drag_report([run_dir]).rows
    cell = row.cell("ALL")
    assert (cell.tasks, cell.tasks_without_runs, cell.runs, cell.error_runs, cell.pass_at_k) == (2, 2, 0, 2, [])
    assert "2 task(s) with only error runs" in CliRunner().invoke(cli, ["report", str(run_dir)]).stdout
