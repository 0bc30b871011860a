"""The episode report: the numbers built from real run directories, and ``scratchworld report``."""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path
from typing import Any

import pytest
from click.testing import CliRunner

from scratchworld_dist._errors import RunDirError
from scratchworld_dist.cli._main import cli, main
from scratchworld_dist.kinds.tasks.report import RunReport, build_report, render_html, render_markdown
from tests.support.run_dirs import HARNESS, OTHER_HARNESS, job, make_run

# -- run directories -----------------------------------------------------------------------


def main_run(run_dir: Path) -> Path:
    """Six planned jobs of one model: two create, one debug retried, one extend error, one compute, one missing."""
    rows = [
        job("c1", "passed", psr=1.0, steps=10, input_tokens=100, output_tokens=10, cost_usd=0.10),
        job("c2", "failed", psr=0.5, steps=20, input_tokens=200, output_tokens=20, cost_usd=0.20),
        job("d1", "error", category="debug", error_class="EpisodeTimeout", cost_usd=0.03, input_tokens=7),
        job("d1", "passed", category="debug", attempt=2, steps=5, input_tokens=50, output_tokens=5, cost_usd=0.05),
        job("e1", "error", category="extend", steps=3, input_tokens=30, output_tokens=3, cost_usd=0.01),
        job("x1", "failed", category="compute", psr=0.0, steps=30, input_tokens=300, output_tokens=30, cost_usd=0.30),
        job("x1", "failed", category="compute", psr=0.0, steps=30, input_tokens=300, output_tokens=30, cost_usd=0.30),
        job("old", "passed", suite_hash="suite0", category="create", cost_usd=5.0),
    ]
    return make_run(run_dir, rows, planned=6, tasks=6)


def test_main_table_numbers(tmp_path: Path) -> None:
    report = build_report([main_run(tmp_path / "run")])
    (row,) = report.rows
    assert (row.label, row.agent, row.model, row.mode) == ("gpt", "llm", "gpt", "composite")
    # x1 delivered twice counts once; d1's error attempt is superseded by its verdict; "old" is stale.
    assert (row.jobs, row.determinate, row.passed, row.errors, row.missing) == (5, 4, 2, 1, 1)
    assert row.sr == pytest.approx(2 / 4)  # the extend error is not a failure
    assert row.psr == pytest.approx((1.0 + 0.5 + 1.0 + 0.0) / 4)
    assert row.coverage == pytest.approx(4 / 6)
    cats = row.categories
    assert (cats["create"].passed, cats["create"].determinate, cats["create"].sr) == (1, 2, 0.5)
    assert (cats["debug"].sr, cats["compute"].sr) == (1.0, 0.0)
    assert (cats["extend"].sr, cats["extend"].determinate, cats["extend"].errors) == (None, 0, 1)
    assert row.mean_steps == pytest.approx((10 + 20 + 5 + 30) / 4)
    assert (row.input_tokens, row.output_tokens) == (100 + 200 + 50 + 30 + 300, 10 + 20 + 5 + 3 + 30)
    assert row.cost_usd == pytest.approx(0.10 + 0.20 + 0.05 + 0.01 + 0.30)
    assert row.cost_per_success == pytest.approx(0.66 / 2)
    assert row.seeds is None

    (run,) = report.runs
    assert (run.planned_jobs, run.recorded_jobs, run.determinate, run.errors, run.missing) == (6, 5, 4, 1, 1)
    assert (run.stale_rows, run.attempts) == (1, 6)
    assert run.attempts_cost_usd == pytest.approx(0.69)
    assert [(e.error_class, e.jobs, e.attempts) for e in report.errors] == [
        ("EditorCrashedError", 1, 1),
        ("EpisodeTimeout", 0, 1),
    ]
    assert report.recovered_jobs == 1
    assert report.categories == ["create", "debug", "extend", "compute"]
    assert any("1 row(s) from an older suite" in w for w in report.warnings)


def test_a_verdict_beats_a_later_error(tmp_path: Path) -> None:
    rows = [job("a", "passed"), job("a", "error", attempt=2), job("b", "failed")]
    report = build_report([make_run(tmp_path / "run", rows, planned=2, tasks=2)])
    (row,) = report.rows
    assert (row.jobs, row.passed, row.errors, row.sr) == (2, 1, 0, 0.5)
    assert report.recovered_jobs == 0
    assert [(e.error_class, e.jobs, e.attempts) for e in report.errors] == [("EditorCrashedError", 0, 1)]


def test_missing_is_run_level_when_the_config_cannot_attribute_it(tmp_path: Path) -> None:
    rows = [job("a", "passed"), job("b", "error")]
    run_dir = make_run(tmp_path / "run", rows, planned=5, tasks=5, config={"something": "else"})
    report = build_report([run_dir])
    (row,) = report.rows
    assert row.missing is None
    assert row.coverage == pytest.approx(1 / 2)
    assert report.runs[0].missing == 3
    assert "Missing: 3 planned job(s)" in render_markdown(report)


def seeds_run(run_dir: Path) -> Path:
    """The oracle over 3 seeds x 2 tasks: task a passes 2 of 3, task b fails twice and errors once."""
    outcomes = {("a", 0): "passed", ("a", 1): "passed", ("a", 2): "failed"}
    outcomes |= {("b", 0): "failed", ("b", 1): "failed", ("b", 2): "error"}
    rows = [
        job(f"{task}{seed}", outcome, task_id=task, seed=seed, agent="oracle", model="-", mode="primitive", cost_usd=0)
        for (task, seed), outcome in outcomes.items()
    ]
    config = {"agent": "oracle", "models": [], "episodes": {"modes": ["primitive"]}, "seeds": [0, 1, 2]}
    return make_run(run_dir, rows, planned=6, tasks=2, config=config)


def test_seed_statistics(tmp_path: Path) -> None:
    report = build_report([seeds_run(tmp_path / "run")])
    (row,) = report.rows
    assert (row.label, row.missing, row.cost_per_success) == ("oracle", 0, 0.0)
    stats = row.seeds
    assert stats is not None
    assert [(s.seed, s.passed, s.determinate) for s in stats.per_seed] == [(0, 1, 2), (1, 1, 2), (2, 0, 1)]
    assert stats.sr is not None
    assert stats.sr.mean == pytest.approx(1 / 3)
    assert stats.sr.half_width == pytest.approx(4.3026527 * math.sqrt(1 / 12) / math.sqrt(3))
    assert [(e.k, e.tasks) for e in stats.pass_at_k] == [(1, 2), (2, 2), (3, 1)]
    assert [e.value for e in stats.pass_at_k] == pytest.approx([1 / 3, 1 / 2, 1.0])
    assert [e.value for e in stats.pass_hat_k] == pytest.approx([1 / 3, 1 / 6, 0.0])
    md = render_markdown(report)
    assert "## Mode: primitive" in md and "pass@3" in md and "pass^3" in md
    assert "| oracle | 0, 1, 2 | 33.3% ± 71.7 pp | 33.3% (2 tasks) | 50.0% (2 tasks) | 100.0% (1 task) |" in md


# -- merging -------------------------------------------------------------------------------


def other_model_run(run_dir: Path, **manifest: Any) -> Path:
    suite = manifest.get("suite_hash", "suite1")
    harness = manifest.get("harness", HARNESS).digest
    rows = [job(j, "passed", model="claude", suite_hash=suite, harness_fingerprint=harness) for j in ("m1", "m2")]
    config = {"agent": "llm", "models": [{"model": "claude"}], "episodes": {"modes": ["composite"]}, "seeds": [0]}
    return make_run(run_dir, rows, planned=2, tasks=2, config=config, name="sweep-b", **manifest)


def test_compatible_runs_merge(tmp_path: Path) -> None:
    report = build_report([main_run(tmp_path / "a"), other_model_run(tmp_path / "b")])
    assert [r.label for r in report.rows] == ["claude", "gpt"]
    assert [r.run_name for r in report.runs] == ["sweep", "sweep-b"]
    claude = report.rows[0]
    assert (claude.sr, claude.coverage, claude.missing) == (1.0, 1.0, 0)
    assert not any("merged anyway" in w for w in report.warnings)


def test_the_same_directory_twice_is_one_run(tmp_path: Path) -> None:
    run_dir = main_run(tmp_path / "a")
    report = build_report([run_dir, tmp_path / "." / "a"])
    assert len(report.runs) == 1 and report.rows[0].jobs == 5


def test_a_job_in_two_runs_counts_once(tmp_path: Path) -> None:
    first = make_run(tmp_path / "a", [job("a", "error"), job("b", "failed")], planned=2, tasks=2)
    second = make_run(tmp_path / "b", [job("a", "passed", attempt=2)], planned=2, tasks=2, name="again")
    report = build_report([first, second])
    (row,) = report.rows
    assert (row.jobs, row.passed, row.errors) == (2, 1, 0)
    assert "1 job(s) appear in more than one run; each is counted once" in report.warnings


@pytest.mark.parametrize(
    ("manifest", "what", "values"),
    [
        ({"suite_hash": "suite2"}, "suite hash", ("suite1", "suite2")),
        (
            {"harness": OTHER_HARNESS},
            "differ in harness",
            (HARNESS.digest, OTHER_HARNESS.digest, "scratch-gui/clock.js"),
        ),
    ],
)
def test_incomparable_runs_are_refused_unless_forced(
    tmp_path: Path, manifest: dict[str, Any], what: str, values: tuple[str, ...]
) -> None:
    first, second = main_run(tmp_path / "a"), other_model_run(tmp_path / "b", **manifest)
    with pytest.raises(RunDirError, match=what) as caught:
        build_report([first, second])
    message = str(caught.value)
    assert all(v in message for v in values) and "sweep-b" in message and str(first) in message
    assert "--force" in message
    assert "workers/_evaluation.py" not in message  # only the parts that differ are named
    forced = build_report([first, second], force=True)
    assert any(w.startswith("merged anyway (--force): ") and what in w for w in forced.warnings)
    assert len(forced.rows) == 2


def test_unusable_run_directories(tmp_path: Path) -> None:
    with pytest.raises(RunDirError, match="not a scratchworld run directory"):
        build_report([tmp_path / "nope"])
    (tmp_path / "bare").mkdir()
    with pytest.raises(RunDirError, match=r"no manifest\.json"):
        build_report([tmp_path / "bare"])
    with pytest.raises(RunDirError, match="no job results yet"):
        build_report([make_run(tmp_path / "empty", [], planned=3, tasks=3)])
    with pytest.raises(RunDirError, match="no run directory given"):
        build_report([])


# -- rendering -----------------------------------------------------------------------------


def test_markdown_main_table(tmp_path: Path) -> None:
    md = render_markdown(build_report([main_run(tmp_path / "run")]))
    header = next(line for line in md.splitlines() if line.startswith("| agent/model"))
    assert header.split(" | ")[1:7] == ["Create SR", "Debug SR", "Extend SR", "Compute SR", "SR", "PSR"]
    gpt = next(line for line in md.splitlines() if line.startswith("| gpt |"))
    cells = [c.strip() for c in gpt.strip("|").split("|")]
    assert cells[1:8] == ["50.0% (1/2)", "100.0% (1/1)", "-", "0.0% (0/1)", "50.0% (2/4)", "62.5%", "66.7% (4/6)"]
    assert cells[8:] == ["1", "16.2", "748", "$0.6600", "$0.3300"]
    assert "| EditorCrashedError | 1 | 1 |" in md
    assert "Recovered: 1 job(s)" in md
    assert "Missing: 1 planned job(s)" in md


def test_a_human_baseline_puts_every_rows_time_per_task_beside_its_rates(tmp_path: Path) -> None:
    """Rows of the human agent (no model) sit beside the model's, and the table gains the time per task."""
    rows = [
        job("c1", "passed", mode="primitive", agent_s=12.0),
        job("c2", "failed", mode="primitive", agent_s=20.0),
        *(job(f"h{n}", outcome, agent="human", model="-", mode="primitive", agent_s=seconds)
          for n, outcome, seconds in ((1, "passed", 100.0), (2, "passed", 300.0), (3, "error", 900.0))),
    ]  # fmt: skip
    report = build_report([make_run(tmp_path / "run", rows, planned=5, tasks=5)])
    human = next(row for row in report.rows if row.agent == "human")
    assert (human.label, human.sr, human.errors, human.mean_agent_s) == ("human", 1.0, 1, 200.0)  # errors: no time
    md = render_markdown(report)
    header = [c.strip() for c in next(line for line in md.splitlines() if line.startswith("| agent/model")).split("|")]
    at = header.index("time per task")
    cells = {line.split("|")[1].strip(): line.split("|") for line in md.splitlines() if line.startswith("| ")}
    assert (cells["human"][at].strip(), cells["gpt"][at].strip()) == ("200.0 s", "16.0 s")
    models_only = render_markdown(build_report([main_run(tmp_path / "models")]))
    assert "time per task" not in models_only  # a report without a person keeps its columns


def test_html_is_self_contained_and_escaped(tmp_path: Path) -> None:
    rows = [job("a", "passed", model="<b>gpt&co</b>"), job("b", "error", error_class="<script>x</script>")]
    config = {
        "agent": "llm",
        "models": [{"model": "<b>gpt&co</b>"}],
        "episodes": {"modes": ["composite"]},
        "seeds": [0],
    }
    page = render_html(build_report([make_run(tmp_path / "run", rows, planned=2, tasks=2, config=config)]))
    assert page.startswith("<!DOCTYPE html>") and page.rstrip().endswith("</html>")
    assert "&lt;b&gt;gpt&amp;co&lt;/b&gt;" in page and "<b>gpt" not in page
    assert "&lt;script&gt;x&lt;/script&gt;" in page and "<script" not in page
    assert "http" not in page and "<link" not in page


def test_markdown_escapes_pipes(tmp_path: Path) -> None:
    run_dir = make_run(tmp_path / "run", [job("a", model="a|b")], planned=1, tasks=1, config={})
    assert "| a\\|b |" in render_markdown(build_report([run_dir]))


# -- the command ---------------------------------------------------------------------------


def test_cli_markdown_to_stdout(tmp_path: Path) -> None:
    result = CliRunner().invoke(cli, ["report", str(main_run(tmp_path / "run"))])
    assert result.exit_code == 0, result.output
    assert result.stdout.startswith("# ScratchWorld report")
    assert "| gpt |" in result.stdout and "## Mode: composite" in result.stdout


def test_cli_json_is_the_report_model(tmp_path: Path) -> None:
    result = CliRunner().invoke(cli, ["report", str(main_run(tmp_path / "run")), "--format", "json"])
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert data["version"] == 1
    assert set(data) == {"version", "runs", "warnings", "categories", "rows", "errors", "recovered_jobs"}
    report = RunReport.model_validate(data)
    assert (report.rows[0].passed, report.rows[0].determinate, report.runs[0].missing) == (2, 4, 1)


def test_cli_html_to_file(tmp_path: Path) -> None:
    out = tmp_path / "report.html"
    result = CliRunner().invoke(cli, ["report", str(main_run(tmp_path / "run")), "--format", "html", "--out", str(out)])
    assert result.exit_code == 0, result.output
    assert result.stdout == ""
    assert f"wrote html report to {out}" in result.stderr
    assert out.read_text(encoding="utf-8").startswith("<!DOCTYPE html>")


def test_cli_refuses_incomparable_runs_unless_forced(tmp_path: Path) -> None:
    args = ["report", str(main_run(tmp_path / "a")), str(other_model_run(tmp_path / "b", suite_hash="suite2"))]
    refused = CliRunner().invoke(cli, args)
    assert isinstance(refused.exception, RunDirError) and "suite hash" in str(refused.exception)
    assert refused.stdout == ""
    forced = CliRunner().invoke(cli, [*args, "--force"])
    assert forced.exit_code == 0, forced.output
    assert "Warning: merged anyway (--force): runs differ in suite hash" in forced.stdout
    assert "warning: merged anyway" in forced.stderr


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (lambda root: root / "nope", "not a scratchworld run directory"),
        (lambda root: make_run(root / "empty", [], planned=1, tasks=1), "no job results yet"),
    ],
)
def test_cli_user_errors_exit_2(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str], make: Any, message: str
) -> None:
    monkeypatch.setattr(sys, "argv", ["scratchworld", "report", str(make(tmp_path))])
    with pytest.raises(SystemExit) as exited:
        main()
    assert exited.value.code == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and message in err


def test_cli_needs_a_run_dir() -> None:
    result = CliRunner().invoke(cli, ["report"])
    assert result.exit_code == 2 and "Missing argument" in result.output
