"""``compare`` of three systems or more: ranked by SR, every pair tested, McNemar's p-values adjusted by Holm."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from scratchworld_dist.kinds.tasks.report import holm
from tests.support.cli_runner import invoke
from tests.support.run_dirs import job, make_run


def run_of(tmp_path: Path, model: str, passes: int, tasks: int = 12) -> Path:
    rows = [
        job(
            f"{model}-{n}", "passed" if n < passes else "failed", model=model, task_id=f"task{n:02d}", task_hash=f"h{n}"
        )
        for n in range(tasks)
    ]
    return make_run(tmp_path / model, rows, planned=tasks, tasks=tasks, name=model)


def test_holm_scales_the_kth_smallest_p_by_the_hypotheses_left_and_keeps_it_monotone() -> None:
    assert holm([0.01, 0.04, 0.03, 0.005]) == pytest.approx([0.03, 0.06, 0.06, 0.02])
    assert holm([0.5, 0.9]) == [1.0, 1.0]  # capped at 1
    assert holm([]) == []


def test_three_systems_are_ranked_and_every_pair_is_tested_with_holm(tmp_path: Path) -> None:
    best, middle, worst = run_of(tmp_path, "best", 12), run_of(tmp_path, "middle", 6), run_of(tmp_path, "worst", 0)
    done = invoke("compare", str(worst), str(best), str(middle), "--format", "json", "--resamples", "200")
    assert done.returncode == 0, done.stderr
    ranking = json.loads(done.stdout)
    assert [(s["rank"], s["label"], s["sr"]) for s in ranking["systems"]] == [
        (1, "best", 1.0), (2, "middle", 0.5), (3, "worst", 0.0),
    ]  # fmt: skip
    pairs = {(p["a"], p["b"]): p for p in ranking["pairs"]}
    assert set(pairs) == {("worst", "best"), ("worst", "middle"), ("best", "middle")}
    extreme = pairs[("worst", "best")]  # 12 discordant pairs all one way: p = 2 / 2**12
    assert extreme["p_value"] == pytest.approx(2 / 4096) and extreme["sr_difference"] == -1.0
    assert [p["p_holm"] for p in ranking["pairs"]] == pytest.approx(holm([p["p_value"] for p in ranking["pairs"]]))
    assert extreme["significant"] and pairs[("worst", "middle")]["significant"] is not None
    text = invoke("compare", str(worst), str(best), str(middle), "--resamples", "200").stdout
    assert text.startswith("# Ranking") and "p (Holm)" in text
