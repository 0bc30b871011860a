"""The report's plots: each plot's table holds the numbers computed here by hand, and the page shows them safely."""

from __future__ import annotations

import math
import re
from datetime import timedelta
from pathlib import Path

import numpy as np
import pytest

from scratchworld_dist.kinds.tasks.report import report_plots
from scratchworld_dist.kinds.tasks.report._plots import bin_width, pareto_front
from scratchworld_dist.reports import Plot, plots_html
from scratchworld_dist.results import JobRow
from tests.support.cli_runner import invoke
from tests.support.run_dirs import T0, job, make_run

TASKS = {"t0": "create", "t1": "debug", "t2": "extend", "t3": "compute"}
SEEDS = (0, 1, 2)
PASSING_SEEDS = {  # per (model, mode): of each task, how many seeds (the first ones) pass
    ("alpha", "composite"): {"t0": 3, "t1": 2, "t2": 1, "t3": 0},
    ("alpha", "primitive"): {"t0": 1, "t1": 1, "t2": 0, "t3": 0},
    ("beta", "composite"): {"t0": 3, "t1": 3, "t2": 2, "t3": 1},
    ("beta", "primitive"): {"t0": 2, "t1": 0, "t2": 0, "t3": 0},
}
COST_PER_JOB = {
    ("alpha", "composite"): 0.1,
    ("alpha", "primitive"): 0.2,
    ("beta", "composite"): 0.15,
    ("beta", "primitive"): 0.05,
}
ERROR_JOB = ("beta", "primitive", 2, "t3")
"""Never decided: two error attempts, then nothing (excluded from SR, counted in cost)."""


def _steps(seed: int, task: str) -> int:
    return 4 + 3 * seed + int(task[1])


def _finished(model: str, mode: str, seed: int, task: str) -> timedelta:
    return timedelta(minutes=30 * seed + 5 * int(task[1]) + 2 * (mode == "primitive") + (model == "beta"))


def sweep_rows(models: tuple[str, str] = ("alpha", "beta")) -> list[JobRow]:
    """Two models, both modes, three seeds, four tasks; one job retried after an error, one never decided."""
    rename = dict(zip(("alpha", "beta"), models, strict=True))
    rows = []
    for (model, mode), passing in PASSING_SEEDS.items():
        for seed in SEEDS:
            for task, category in TASKS.items():
                key = f"{model}-{mode}-{seed}-{task}"
                common = {"model": rename[model], "mode": mode, "seed": seed, "task_id": task, "category": category}
                common["cost_usd"] = COST_PER_JOB[(model, mode)]
                when = T0 + _finished(model, mode, seed, task)
                if (model, mode, seed, task) == ERROR_JOB:
                    rows.append(
                        job(
                            key,
                            "error",
                            error_class="episode_timeout",
                            finished_at=T0 + timedelta(minutes=61),
                            **common,
                        )
                    )
                    rows.append(
                        job(
                            key,
                            "error",
                            attempt=2,
                            error_class="worker_died",
                            finished_at=T0 + timedelta(minutes=63),
                            **common,
                        )
                    )
                    continue
                outcome = "passed" if seed < passing[task] else "failed"
                rows.append(job(key, outcome, steps=_steps(seed, task), finished_at=when, **common))
    retried = "alpha-composite-0-t0"  # its error attempt is superseded: not in SR nor cost
    first = next(r for r in rows if r.job_id == retried)
    rows.append(first.model_copy(update={"attempt": 2}))
    rows[rows.index(first)] = job(
        retried, "error", model=first.model, task_id="t0", seed=0, cost_usd=0.5, error_class="worker_died",
        finished_at=T0 + timedelta(minutes=2),
    )  # fmt: skip
    return rows


def sweep(run_dir: Path, models: tuple[str, str] = ("alpha", "beta")) -> Path:
    config = {
        "agent": "llm",
        "models": [{"model": m} for m in models],
        "episodes": {"modes": ["composite", "primitive"]},
    }
    config["seeds"] = list(SEEDS)
    return make_run(run_dir, sweep_rows(models), planned=48, tasks=4, config=config)


@pytest.fixture(scope="module")
def plots(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Plot]:
    return {p.key: p for p in report_plots([sweep(tmp_path_factory.mktemp("plots") / "run")])}


def _decided(model: str, mode: str) -> dict[str, list[bool]]:
    """Per task, the verdicts of the jobs with one (by seed)."""
    passing = PASSING_SEEDS[(model, mode)]
    return {task: [seed < passing[task] for seed in SEEDS if (model, mode, seed, task) != ERROR_JOB] for task in TASKS}


def _rate(verdicts: list[bool]) -> str:
    return f"{100 * sum(verdicts) / len(verdicts):.1f}% ({sum(verdicts)}/{len(verdicts)})"


def _overall(model: str, mode: str) -> list[bool]:
    return [v for verdicts in _decided(model, mode).values() for v in verdicts]


def _sr(model: str, mode: str) -> float:
    verdicts = _overall(model, mode)
    return sum(verdicts) / len(verdicts)


GROUPS = sorted(PASSING_SEEDS, key=lambda group: (group[1], group[0]))
"""Table order: by mode, then label."""


def test_plots_in_order(plots: dict[str, Plot]) -> None:
    expected = ["sr_by_category", "reasoning_acting_gap", "cost_vs_sr", "pass_at_k", "steps_to_success"]
    assert list(plots) == [*expected, "errors_over_time"]


def test_sr_by_category_is_table_1(plots: dict[str, Plot]) -> None:
    plot = plots["sr_by_category"]
    assert plot.headers == ["agent/model", "mode", "create", "debug", "extend", "compute", "overall"]
    expected = [
        [model, mode, *(_rate(_decided(model, mode)[t]) for t in TASKS), _rate(_overall(model, mode))]
        for model, mode in GROUPS
    ]
    assert plot.rows == expected
    assert ["beta", "primitive", "66.7% (2/3)", "0.0% (0/3)", "0.0% (0/3)", "0.0% (0/2)", "18.2% (2/11)"] in plot.rows


def test_gap_is_composite_minus_primitive(plots: dict[str, Plot]) -> None:
    plot = plots["reasoning_acting_gap"]
    assert plot.headers == ["agent/model", "composite SR", "primitive SR", "gap (composite - primitive)"]
    expected = [
        [m, _rate(_overall(m, "composite")), _rate(_overall(m, "primitive")), f"{gap:+.1f} pp"]
        for m, gap in (("alpha", 100 * (6 / 12 - 2 / 12)), ("beta", 100 * (9 / 12 - 2 / 11)))
    ]
    assert plot.rows == expected
    assert [row[3] for row in plot.rows] == ["+33.3 pp", "+56.8 pp"]


def test_cost_vs_sr_marks_the_pareto_front(plots: dict[str, Plot]) -> None:
    plot = plots["cost_vs_sr"]
    costs = {group: 12 * COST_PER_JOB[group] for group in GROUPS}  # effective jobs; the retried error not
    on_front = {
        a
        for a in GROUPS
        if not any(
            costs[b] <= costs[a] and _sr(*b) >= _sr(*a) and (costs[b], _sr(*b)) != (costs[a], _sr(*a)) for b in GROUPS
        )
    }
    assert on_front == {("alpha", "composite"), ("beta", "composite"), ("beta", "primitive")}
    usd = {group: f"${cost:.4f}" if cost < 1 else f"${cost:,.2f}" for group, cost in costs.items()}
    expected = [
        [m, mode, usd[m, mode], _rate(_overall(m, mode)), "yes" if (m, mode) in on_front else "no"]
        for m, mode in GROUPS
    ]
    assert plot.rows == expected


def test_pareto_front_keeps_one_of_equal_points_and_drops_the_dominated() -> None:
    assert pareto_front([(1.0, 0.5), (1.0, 0.5), (2.0, 0.5), (0.5, 0.2), (3.0, 0.9), (3.0, 0.8)]) == {0, 3, 4}
    assert pareto_front([]) == set()


def _pass_at_k(n: int, c: int, k: int) -> float:
    return 1.0 - math.comb(n - c, k) / math.comb(n, k)


def test_pass_at_k_per_seed_count(plots: dict[str, Plot]) -> None:
    plot = plots["pass_at_k"]
    assert plot.headers == ["agent/model", "mode", "pass@1", "pass@2", "pass@3"]
    expected = []
    for model, mode in GROUPS:
        counts = [(len(v), sum(v)) for v in _decided(model, mode).values()]
        values = [np.mean([_pass_at_k(n, c, k) for n, c in counts if n >= k]) for k in (1, 2, 3)]
        expected.append([model, mode, *(f"{100 * v:.1f}%" for v in values)])
    assert plot.rows == expected
    assert expected[0] == ["alpha", "composite", "50.0%", "66.7%", "75.0%"]


def test_steps_to_success_over_passed_jobs(plots: dict[str, Plot]) -> None:
    plot = plots["steps_to_success"]
    assert plot.headers == ["agent/model", "mode", "successes", "min", "Q1", "median", "Q3", "max", "mean"]
    expected = []
    for model, mode in GROUPS:
        passing = PASSING_SEEDS[(model, mode)]
        steps = [_steps(seed, task) for task in TASKS for seed in SEEDS if seed < passing[task]]
        numbers = [min(steps), *np.percentile(steps, [25, 50, 75]), max(steps), np.mean(steps)]
        expected.append([model, mode, str(len(steps)), *(f"{v:.1f}" for v in numbers)])
    assert plot.rows == expected


def test_errors_over_time_counts_every_error_attempt_per_bin(plots: dict[str, Plot]) -> None:
    plot = plots["errors_over_time"]
    assert plot.headers == ["bin start (UTC)", "worker_died", "episode_timeout", "total"]
    # The run spans 77 minutes: 5-minute bins from 00:00 to 01:15.
    assert len(plot.rows) == 16
    assert [row[0] for row in plot.rows[:2]] == ["2026-01-01 00:00", "2026-01-01 00:05"]
    assert plot.rows[-1][0] == "2026-01-01 01:15"
    nonzero = {row[0]: row[1:] for row in plot.rows if row[-1] != "0"}
    assert nonzero == {"2026-01-01 00:00": ["1", "0", "1"], "2026-01-01 01:00": ["1", "1", "2"]}
    assert "5 min" in plot.caption


@pytest.mark.parametrize(
    ("span", "width"),
    [
        (timedelta(0), timedelta(minutes=1)),
        (timedelta(minutes=29), timedelta(minutes=1)),
        (timedelta(minutes=30), timedelta(minutes=5)),
        (timedelta(hours=20), timedelta(hours=1)),
        (timedelta(days=400), timedelta(days=14)),
    ],
)
def test_bins_are_usual_widths_and_at_most_30(span: timedelta, width: timedelta) -> None:
    assert bin_width(span) == width
    assert span / width < 30


def test_plots_with_nothing_to_show_are_left_out(tmp_path: Path) -> None:
    # One scripted agent, one mode, one seed, no cost, no error: no gap, front, pass@k or errors over time.
    rows = [job("a", "passed", agent="oracle", model="-", cost_usd=0.0), job("b", "failed", agent="oracle", model="-")]
    rows[1] = rows[1].model_copy(update={"cost_usd": 0.0})
    config = {"agent": "oracle", "models": None, "episodes": {"modes": ["composite"]}, "seeds": [0]}
    plots = report_plots([make_run(tmp_path / "run", rows, planned=2, tasks=2, config=config)])
    assert [p.key for p in plots] == ["sr_by_category", "steps_to_success"]
    assert plots[0].rows == [["oracle", "composite", "50.0% (1/2)", "50.0% (1/2)"]]


def test_drag_runs_get_no_episode_plots(tmp_path: Path) -> None:
    rows = [job("a", "passed", setting="baseline", category="T1"), job("b", "failed", setting="gt_start")]
    assert report_plots([make_run(tmp_path / "run", rows, planned=2, tasks=2)]) == []


def test_html_has_a_figure_per_plot_with_its_table(plots: dict[str, Plot]) -> None:
    page = plots_html(list(plots.values()))
    assert page.startswith("<section") and page.endswith("</section>")
    for name in ("<svg", "<figure", "<figcaption", "<table"):
        assert page.count(name) == len(plots), name
    for plot in plots.values():
        cells = "".join(f"<td>{cell}</td>" for cell in plot.rows[0])
        assert f"<tr>{cells}</tr>" in page.replace("&#x27;", "'")
    ids = re.findall(r'\bid="([^"]+)"', page)
    assert len(ids) == len(set(ids)), "two plots share an id"
    assert "<script" not in page and "<link" not in page and "<?xml" not in page
    assert plots_html([]) == ""


def test_rendering_twice_gives_the_same_svg(tmp_path: Path) -> None:
    run = sweep(tmp_path / "run")
    first, second = report_plots([run]), report_plots([run])
    assert [p.svg for p in first] == [p.svg for p in second]
    assert all(p.svg.startswith("<svg") and p.svg.endswith("</svg>") for p in first)


def test_hostile_model_names_are_escaped_everywhere(tmp_path: Path) -> None:
    hostile = "<script>alert(1)</script> $5"
    done = invoke("report", str(sweep(tmp_path / "run", models=("alpha", hostile))), "--format", "html")
    assert done.returncode == 0, done.stderr
    page = done.stdout
    assert "<script" not in page
    assert page.count("alert(1)") == page.count("&lt;script&gt;alert(1)&lt;/script&gt;") > 0
    assert page.count("<svg") == 6 and '<section class="sw-plots">' in page


def test_cli_html_report_has_the_plots_after_the_tables_and_md_has_none(tmp_path: Path) -> None:
    run = str(sweep(tmp_path / "run"))
    page = invoke("report", run, "--format", "html").stdout
    assert page.index("<h2>Errors</h2>") < page.index('<section class="sw-plots">') < page.index("</body>")
    for title in ("Success rate by category", "Reasoning-acting gap", "Cost vs success rate", "pass@k"):
        assert f"<strong>{title}</strong>" in page
    markdown = invoke("report", run).stdout
    assert "<svg" not in markdown and "Plots" not in markdown
