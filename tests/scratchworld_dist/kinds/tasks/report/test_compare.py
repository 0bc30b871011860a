"""``scratchworld compare``: pairing, the interval and p-value against independent computations, refusals."""

from __future__ import annotations

import json
import math
import sys
from datetime import timedelta
from itertools import pairwise
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from click.testing import CliRunner

from scratchworld_dist._errors import RunDirError
from scratchworld_dist.cli._main import cli, main
from scratchworld_dist.kinds.tasks.report import Comparison, Selector, compare_runs, parse_selector, render_comparison
from scratchworld_dist.reports import mcnemar_exact, paired_bootstrap
from scratchworld_dist.results import JobRow
from tests.support.run_dirs import HARNESS, OTHER_HARNESS, T0, job, make_run, regrade_run

# -- the statistics, against computations of this file ----------------------------------------


def _exact_mcnemar(only_a: int, only_b: int) -> float:
    """Two-sided exact McNemar p: twice the smaller binomial tail of the discordant pairs, at most 1."""
    n = only_a + only_b
    tail = sum(math.comb(n, i) for i in range(min(only_a, only_b) + 1)) / 2**n
    return min(1.0, 2 * tail)


@pytest.mark.parametrize(("only_a", "only_b"), [(1, 8), (8, 1), (5, 5), (0, 6), (3, 0), (12, 4), (1, 0)])
def test_mcnemar_is_the_exact_binomial_test_on_discordant_pairs(only_a: int, only_b: int) -> None:
    pairs = [(1.0, 0.0)] * only_a + [(0.0, 1.0)] * only_b + [(1.0, 1.0)] * 4 + [(0.0, 0.0)] * 2
    result = mcnemar_exact(pairs)
    assert (result.only_a, result.only_b, result.both_passed, result.neither) == (only_a, only_b, 4, 2)
    assert result.p_value == pytest.approx(_exact_mcnemar(only_a, only_b), rel=1e-9)


def test_mcnemar_without_discordant_pairs_finds_nothing() -> None:
    assert mcnemar_exact([(1.0, 1.0), (0.0, 0.0)]).p_value == 1.0


def _exact_bootstrap_quantiles(wins: int, ties: int, losses: int) -> tuple[float, float]:
    """The 2.5% and 97.5% quantiles of the exact bootstrap distribution of the mean difference.

    One pair per task with a difference of +1, 0 or -1: a resample of n tasks draws k+ wins and
    k- losses with multinomial probability, and its mean difference is (k+ - k-) / n.
    """
    n = wins + ties + losses
    p = (wins / n, ties / n, losses / n)
    mass: dict[float, float] = {}
    for k_win in range(n + 1):
        for k_loss in range(n - k_win + 1):
            k_tie = n - k_win - k_loss
            ways = math.factorial(n) // (math.factorial(k_win) * math.factorial(k_tie) * math.factorial(k_loss))
            probability = ways * p[0] ** k_win * p[1] ** k_tie * p[2] ** k_loss
            value = (k_win - k_loss) / n
            mass[value] = mass.get(value, 0.0) + probability
    values = sorted(mass)
    cumulative = np.cumsum([mass[v] for v in values])
    low = values[int(np.searchsorted(cumulative, 0.025))]
    high = values[int(np.searchsorted(cumulative, 0.975))]
    return low, high


@pytest.mark.parametrize(("wins", "ties", "losses"), [(9, 11, 4), (3, 20, 7), (10, 2, 0)])
def test_the_bootstrap_interval_matches_the_exact_bootstrap_distribution(wins: int, ties: int, losses: int) -> None:
    clusters = [[(1.0, 0.0)]] * wins + [[(1.0, 1.0)]] * ties + [[(0.0, 1.0)]] * losses
    interval = paired_bootstrap(clusters, resamples=20_000, seed=3)
    low, high = _exact_bootstrap_quantiles(wins, ties, losses)
    atom = 1 / len(clusters)  # the exact distribution moves in steps of one task
    assert interval.low == pytest.approx(low, abs=atom + 1e-9)
    assert interval.high == pytest.approx(high, abs=atom + 1e-9)
    assert interval.low <= (wins - losses) / len(clusters) <= interval.high


def test_the_bootstrap_is_reproducible_by_seed_and_a_constant_difference_is_a_point() -> None:
    clusters = [[(1.0, 0.0), (0.0, 0.0)], [(1.0, 1.0)], [(0.0, 1.0), (1.0, 0.0), (1.0, 1.0)]]
    first = paired_bootstrap(clusters, resamples=2000, seed=7)
    assert first == paired_bootstrap(clusters, resamples=2000, seed=7)
    assert first.low < first.high
    constant = paired_bootstrap([[(1.0, 0.0)], [(1.0, 0.0), (1.0, 0.0)]], resamples=2000, seed=7)
    assert (constant.low, constant.high) == (1.0, 1.0)


# -- selectors -------------------------------------------------------------------------------


def test_selectors_name_a_run_a_system_and_a_mode(tmp_path: Path) -> None:
    run = tmp_path / "run"
    odd = tmp_path / "odd:name@primitive"
    run.mkdir()
    odd.mkdir()
    assert parse_selector(str(run)) == Selector(run)
    assert parse_selector(f"{run}:gpt") == Selector(run, "gpt")
    assert parse_selector(f"{run}@primitive") == Selector(run, None, "primitive")
    assert parse_selector(f"{run}:openai/gpt:4o@composite") == Selector(run, "openai/gpt:4o", "composite")
    assert parse_selector(str(odd)) == Selector(odd)  # the directory wins over a reading of its name
    assert parse_selector(f"{odd}:gpt") == Selector(odd, "gpt")
    with pytest.raises(RunDirError, match="not a scratchworld run directory"):
        parse_selector(str(tmp_path / "nope:gpt"))
    with pytest.raises(RunDirError, match="empty system name"):
        parse_selector(f"{run}:")


# -- comparisons of hand-made runs -----------------------------------------------------------

A_WINS, B_WINS, BOTH, NEITHER = 7, 2, 5, 4


def _jobs(model: str, outcomes: dict[str, str], **fields: Any) -> list[JobRow]:
    return [
        job(f"{model}-{task}", outcome, model=model, task_id=task, task_hash=f"t{task}", **fields)
        for task, outcome in outcomes.items()
    ]


def _two_runs(root: Path) -> tuple[Path, Path]:
    """gpt and claude on 18 shared tasks (7 only gpt passes, 2 only claude, 5 both, 4 neither), plus extras."""
    tasks = [f"task{i:02d}" for i in range(A_WINS + B_WINS + BOTH + NEITHER)]
    kinds = ["a"] * A_WINS + ["b"] * B_WINS + ["both"] * BOTH + ["neither"] * NEITHER
    gpt = {t: "passed" if k in ("a", "both") else "failed" for t, k in zip(tasks, kinds, strict=True)}
    claude = {t: "passed" if k in ("b", "both") else "failed" for t, k in zip(tasks, kinds, strict=True)}
    gpt |= {"only-gpt": "passed", "errored": "error"}
    claude |= {"errored": "passed"}
    a = make_run(root / "a", _jobs("gpt", gpt), planned=len(gpt), tasks=len(gpt))
    b = make_run(root / "b", _jobs("claude", claude), planned=len(claude), tasks=len(claude))
    return a, b


def test_two_runs_compare_on_the_jobs_both_decided(tmp_path: Path) -> None:
    a, b = _two_runs(tmp_path)
    result = compare_runs(Selector(a), Selector(b), resamples=5000)
    assert (result.a.label, result.b.label) == ("gpt", "claude")
    assert result.paired_by == ["task", "seed", "mode", "setting"]
    n = A_WINS + B_WINS + BOTH + NEITHER
    assert (result.paired_jobs, result.tasks) == (n, n)
    assert (result.only_a, result.only_b, result.without_verdict) == (1, 0, 1)
    assert result.sr is not None and result.psr is not None
    assert result.sr.a == pytest.approx((A_WINS + BOTH) / n)
    assert result.sr.b == pytest.approx((B_WINS + BOTH) / n)
    assert result.sr.difference == pytest.approx((A_WINS - B_WINS) / n)
    assert result.psr.difference == pytest.approx(result.sr.difference)  # psr is 1 or 0 in these rows
    low, high = _exact_bootstrap_quantiles(A_WINS, BOTH + NEITHER, B_WINS)
    assert result.sr.interval is not None
    assert result.sr.interval.low == pytest.approx(low, abs=1 / n + 1e-9)
    assert result.sr.interval.high == pytest.approx(high, abs=1 / n + 1e-9)
    m = result.mcnemar
    assert (m.only_a, m.only_b, m.both_passed, m.neither) == (A_WINS, B_WINS, BOTH, NEITHER)
    assert m.p_value == pytest.approx(_exact_mcnemar(A_WINS, B_WINS))
    results = [t.result for t in result.per_task]
    assert (results.count("win"), results.count("loss"), results.count("tie")) == (A_WINS, B_WINS, BOTH + NEITHER)
    assert result.warnings == []


def test_seeds_are_paired_and_resampled_with_their_task(tmp_path: Path) -> None:
    rng = np.random.default_rng(11)
    outcomes = {(t, s): (rng.random() < 0.7, rng.random() < 0.4) for t in range(12) for s in range(3)}
    rows = [
        job(
            f"{model}-{t}-{s}",
            "passed" if won[i] else "failed",
            model=model,
            task_id=f"t{t}",
            task_hash=f"h{t}",
            seed=s,
        )
        for (t, s), won in outcomes.items()
        for i, model in enumerate(("gpt", "claude"))
    ]
    run = make_run(tmp_path / "run", rows, planned=len(rows), tasks=12)
    result = compare_runs(Selector(run, "gpt"), Selector(run, "claude"), resamples=20_000, seed=1)
    assert (result.paired_jobs, result.tasks) == (36, 12)
    assert {t.jobs for t in result.per_task} == {3}
    assert any("McNemar's test treats every job as independent" in w for w in result.warnings)
    # an independent cluster bootstrap: draw 12 tasks with replacement, pool their 3 seeds
    diffs = np.array([[a - b for s in range(3) for a, b in [outcomes[(t, s)]]] for t in range(12)], dtype=float)
    draws = np.random.default_rng(99).integers(0, 12, size=(40_000, 12))
    means = diffs[draws].mean(axis=(1, 2))
    assert result.sr is not None and result.sr.interval is not None
    atom = 1 / 36
    assert result.sr.interval.low == pytest.approx(np.percentile(means, 2.5), abs=atom + 1e-9)
    assert result.sr.interval.high == pytest.approx(np.percentile(means, 97.5), abs=atom + 1e-9)
    assert result.sr.difference == pytest.approx(diffs.mean())


def _two_modes(root: Path) -> Path:
    """gpt passes 6 of 8 tasks in composite mode and 2 in primitive; claude ran composite only."""
    rows = [
        job(
            f"gpt-{mode}-{t}",
            "passed" if t < passed else "failed",
            model="gpt",
            task_id=f"t{t}",
            task_hash=f"h{t}",
            mode=mode,
        )
        for mode, passed in (("composite", 6), ("primitive", 2))
        for t in range(8)
    ]
    rows += [job(f"claude-{t}", "passed", model="claude", task_id=f"t{t}", task_hash=f"h{t}") for t in range(8)]
    return make_run(root / "run", rows, planned=len(rows), tasks=8)


def test_a_models_modes_compare_as_the_reasoning_acting_gap(tmp_path: Path) -> None:
    run = _two_modes(tmp_path)
    gap = compare_runs(parse_selector(f"{run}:gpt@composite"), parse_selector(f"{run}:gpt@primitive"))
    assert gap.paired_by == ["task", "seed", "setting"]
    assert gap.sr is not None
    assert (gap.sr.a, gap.sr.b, gap.paired_jobs) == (0.75, 0.25, 8)
    assert (gap.mcnemar.only_a, gap.mcnemar.only_b) == (4, 0)
    table = render_comparison(gap, "md")
    assert table.startswith("# gpt@composite vs gpt@primitive\n")
    assert "| task | category | A passed | B passed | A |" in table and "| t2 | create | 1/1 | 0/1 | win |" in table
    within = compare_runs(parse_selector(f"{run}:gpt"), parse_selector(f"{run}:claude"))
    assert (within.paired_jobs, within.only_a) == (8, 8)  # claude has no primitive jobs to pair with
    with pytest.raises(RunDirError, match="ran composite, primitive: with a mode named on one side"):
        compare_runs(parse_selector(f"{run}:claude@composite"), parse_selector(f"{run}:gpt"))
    with pytest.raises(RunDirError, match="has no primitive jobs"):
        compare_runs(parse_selector(f"{run}:claude@primitive"), parse_selector(f"{run}:gpt@primitive"))


def test_a_run_of_several_systems_needs_one_named(tmp_path: Path) -> None:
    run = _two_modes(tmp_path)
    with pytest.raises(RunDirError, match=r"holds 2 systems \(claude, gpt\); name one as RUN_DIR:SYSTEM"):
        compare_runs(Selector(run), Selector(run, "gpt"))
    with pytest.raises(RunDirError, match=r"has no system 'llama' \(it has: claude, gpt\)"):
        compare_runs(Selector(run, "llama"), Selector(run, "gpt"))
    with pytest.raises(RunDirError, match="'llm' names 2 systems"):
        compare_runs(Selector(run, "llm"), Selector(run, "gpt"))


@pytest.mark.parametrize(
    ("change", "what"),
    [
        ({"suite_hash": "suite2"}, "differ in suite hash"),
        ({"harness": OTHER_HARNESS}, "differ in harness"),
        ({"eval_clock": "real"}, "eval_clock differs (virtual / real)"),
        ({"eval_profile": "upstream"}, "eval_profile differs (native / upstream)"),
        ({"task_hash": "changed"}, "3 task(s) differ in content"),
    ],
)
def test_incomparable_conditions_are_refused_unless_forced(tmp_path: Path, change: dict[str, Any], what: str) -> None:
    manifest = {k: v for k, v in change.items() if k in ("suite_hash", "harness")}
    fields = {k: v for k, v in change.items() if k not in manifest}
    base = {"eval_clock": "virtual"}
    a = make_run(tmp_path / "a", [job(f"t{i}", model="gpt", **base) for i in range(3)], planned=3, tasks=3)
    suite_hash, harness = manifest.get("suite_hash", "suite1"), manifest.get("harness", HARNESS)
    current = {"suite_hash": suite_hash, "harness_fingerprint": harness.digest}
    rows_b = [job(f"t{i}", "failed", model="claude", **(base | current | fields)) for i in range(3)]
    b = make_run(tmp_path / "b", rows_b, planned=3, tasks=3, suite_hash=suite_hash, harness=harness)
    with pytest.raises(RunDirError, match="refusing to compare") as refused:
        compare_runs(Selector(a), Selector(b))
    assert what in str(refused.value) and "--force" in str(refused.value)
    forced = compare_runs(Selector(a), Selector(b), force=True)
    assert any(w.startswith("compared anyway (--force): ") and what in w for w in forced.warnings)
    assert forced.paired_jobs == 3


# -- the command -----------------------------------------------------------------------------


def test_cli_prints_the_comparison_and_its_json_is_the_model(tmp_path: Path) -> None:
    a, b = _two_runs(tmp_path)
    md = CliRunner().invoke(cli, ["compare", str(a), str(b), "--resamples", "2000"])
    assert md.exit_code == 0, md.output
    lines = md.stdout.splitlines()
    assert lines[0] == "# gpt vs claude"
    sr = next(line for line in lines if line.startswith("| SR |"))
    assert [c.strip() for c in sr.strip("|").split("|")][:4] == ["SR", "66.7%", "38.9%", "+27.8 pp"]
    assert f"only A passed {A_WINS}, only B passed {B_WINS}" in md.stdout
    assert f"A wins {A_WINS}, loses {B_WINS}, ties {BOTH + NEITHER}" in md.stdout
    assert "| task | mode | category | A passed | B passed | A |" in md.stdout
    assert "| task00 | composite | create | 1/1 | 0/1 | win |" in md.stdout
    as_json = CliRunner().invoke(cli, ["compare", f"{a}:gpt", f"{b}:claude", "--format", "json", "--seed", "5"])
    assert as_json.exit_code == 0, as_json.output
    comparison = Comparison.model_validate(json.loads(as_json.stdout))
    assert comparison.sr is not None and comparison.sr.interval is not None
    assert comparison.sr.interval.seed == 5 and comparison.sr.interval.resamples == 10_000
    assert [t.task_id for t in comparison.per_task] == sorted(t.task_id for t in comparison.per_task)
    assert all(x.task_id < y.task_id for x, y in pairwise(comparison.per_task))


def test_cli_errors_are_one_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    a, _ = _two_runs(tmp_path)
    monkeypatch.setattr(sys, "argv", ["scratchworld", "compare", f"{a}:llama", str(a)])
    with pytest.raises(SystemExit) as exited:
        main()
    assert exited.value.code == 2
    err = capsys.readouterr().err
    assert err == f"error: {a} has no system 'llama' (it has: gpt)\n"


def test_a_run_with_only_older_results_has_nothing_to_compare(tmp_path: Path) -> None:
    old = make_run(tmp_path / "old", [job("t0", suite_hash="suite0")], planned=1, tasks=1)
    with pytest.raises(RunDirError, match=r"no results of its manifest's suite and harness \(1 older rows\)"):
        compare_runs(Selector(old), Selector(old))


def test_cli_writes_an_html_page_to_a_file(tmp_path: Path) -> None:
    a, b = _two_runs(tmp_path)
    out = tmp_path / "cmp.html"
    result = CliRunner().invoke(cli, ["compare", f"{a}:gpt", str(b), "--format", "html", "--out", str(out)])
    assert result.exit_code == 0, result.output
    assert result.stdout == "" and f"wrote html comparison to {out}" in result.stderr
    page = out.read_text(encoding="utf-8")
    assert page.startswith("<!DOCTYPE html>") and "<pre># gpt vs claude" in page and "http" not in page


def test_a_job_run_again_under_another_config_counts_once_at_its_latest(tmp_path: Path) -> None:
    first = job("gpt-t0-old", "failed", model="gpt", task_id="t0", task_hash="h0", max_steps=10)
    later = job("gpt-t0-new", "passed", model="gpt", task_id="t0", task_hash="h0", finished_at=T0 + timedelta(hours=1))
    other = [job("claude-t0", "failed", model="claude", task_id="t0", task_hash="h0")]
    a = make_run(tmp_path / "a", [later, first], planned=2, tasks=1)
    b = make_run(tmp_path / "b", other, planned=1, tasks=1)
    result = compare_runs(Selector(a), Selector(b))
    assert result.paired_jobs == 1 and result.mcnemar.only_a == 1
    assert "1 job(s) were run again under another config (another job id); the latest counts" in result.warnings


# -- a regrade and its source ----------------------------------------------------------------


def test_a_regrade_is_compared_with_its_source_and_lists_the_changed_verdicts(tmp_path: Path) -> None:
    source = make_run(tmp_path / "a", [job(f"t{i}", eval_clock="virtual") for i in range(3)], planned=3, tasks=3)
    regrade = regrade_run(source, tmp_path / "b", {"t1"})
    forward = compare_runs(Selector(source), Selector(regrade))  # no refusal: the conditions are the point
    assert forward.regrade is not None
    assert forward.regrade.regrading == "b"
    assert forward.regrade.unchanged == 2
    assert [(c.task_id, c.before, c.after, c.tests_before, c.tests_after) for c in forward.regrade.changed] == [
        ("t1", "passed", "failed", "2/2", "1/2")
    ]
    assert not forward.warnings
    text = render_comparison(forward, "md")
    assert "B regrades A" in text and "clock real" in text and "harness bbbb444455556666" in text
    assert "| t1 | 0 | composite | passed -> failed | 2/2 -> 1/2 |" in text
    backward = compare_runs(Selector(regrade), Selector(source))
    assert backward.regrade is not None and backward.regrade.regrading == "a"
    assert [c.task_id for c in backward.regrade.changed] == ["t1"]


def test_a_run_that_regrades_another_source_is_still_refused(tmp_path: Path) -> None:
    source = make_run(tmp_path / "a", [job(f"t{i}", eval_clock="virtual") for i in range(3)], planned=3, tasks=3)
    other = make_run(tmp_path / "other", [job(f"t{i}", eval_clock="virtual") for i in range(3)], planned=3, tasks=3)
    regrade = regrade_run(other, tmp_path / "b", set())
    # ``source`` has the run name the regrade names, but another path and config: not its source.
    source_manifest = (source / "manifest.json").read_text().replace('"config_hash": "c"', '"config_hash": "d"')
    (source / "manifest.json").write_text(source_manifest)
    with pytest.raises(RunDirError, match="refusing to compare"):
        compare_runs(Selector(source), Selector(regrade))
