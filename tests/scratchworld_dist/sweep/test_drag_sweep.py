"""``benchmark: drag`` end to end: configs, the planned matrix and its ids, and a sweep on Ray that resumes."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
import yaml

from scratchworld_dist._errors import ConfigError
from scratchworld_dist._run import plan_run
from scratchworld_dist.results import RunStore
from scratchworld_dist.sweep import load_sweep_config
from tests.conftest import REPO
from tests.support.sweep_driver import run_here
from workers.contract import DragRegions

SUITE = REPO / "drag-tasks"


def write(tmp_path: Path, **fields: Any) -> Path:
    config: dict[str, Any] = {
        "name": "drag-test",
        "benchmark": "drag",
        "suite": str(SUITE),
        "output": str(tmp_path / "run"),
    }
    config.update(fields)
    path = tmp_path / "drag.yaml"
    path.write_text(yaml.safe_dump(config))
    return path


def two_tasks() -> list[str]:
    from scratchworld_dist.kinds.drag.items import load_drag_suite

    tasks = load_drag_suite(SUITE).tasks
    return [
        next(t.id for t in tasks if t.type == "T1" and t.source.kind == "canvas"),
        next(t.id for t in tasks if t.type == "T2" and t.source.kind == "flyout"),
    ]


@pytest.mark.parametrize(
    ("fields", "message"),
    [
        (
            {"agent": "noop"},
            r"agent 'noop' is not registered for the drag benchmark \(registered: jitter, llm, oracle\); "
            "'noop' is an agent of tasks",
        ),
        ({"drag": {"settings": ["baseline", "baseline"]}}, "settings must be distinct"),
        ({"drag": {"settings": ["zoomed"]}}, "drag.settings.0"),
        ({"drag": {"agents": ["oracle", {"name": "jitter", "params": {"sigma_px": 0}}]}}, "sigma_px"),
        ({"drag": {"agents": ["llm"]}}, "needs at least one entry under models"),
        ({"tasks": {"ids": ["no-such-task"]}}, "not in the suites: no-such-task"),
    ],
)
def test_bad_drag_configs_are_one_line_naming_the_field(tmp_path: Path, fields: dict[str, Any], message: str) -> None:
    with pytest.raises(ConfigError, match=message) as caught:
        plan_run(load_sweep_config(write(tmp_path, **fields)))
    assert "\n" not in str(caught.value)


def test_the_matrix_is_agents_models_settings_tasks_seeds_with_stable_ids(tmp_path: Path) -> None:
    ids = two_tasks()
    fields: dict[str, Any] = {
        "tasks": {"ids": ids},
        "seeds": 2,
        "drag": {
            "agents": ["oracle", {"name": "jitter", "params": {"sigma_px": 4}}],
            "settings": ["baseline", "knowledge"],
        },
    }
    plan = plan_run(load_sweep_config(write(tmp_path, **fields)))
    assert len(plan.jobs) == 2 * 2 * 2 * 2  # agents x settings x tasks x seeds (scripted agents: no model column)
    assert len({job.job_id for job in plan.jobs}) == len(plan.jobs)
    assert {job.body.setting for job in plan.jobs} == {"baseline", "knowledge"}
    again = plan_run(load_sweep_config(write(tmp_path, **fields)))
    assert [job.job_id for job in again.jobs] == [job.job_id for job in plan.jobs]
    noisier = dict(fields, drag={**fields["drag"], "agents": ["oracle", {"name": "jitter", "params": {"sigma_px": 5}}]})
    changed = {job.job_id for job in plan_run(load_sweep_config(write(tmp_path, **noisier))).jobs}
    assert len(changed & {job.job_id for job in plan.jobs}) == 8  # the oracle's jobs keep their ids, jitter's change


@pytest.mark.ray
@pytest.mark.browser
@pytest.mark.slow
def test_a_drag_sweep_runs_records_and_resumes(tmp_path: Path, shared_ray: int) -> None:
    config = write(
        tmp_path,
        tasks={"ids": two_tasks()},
        drag={
            "agents": ["oracle", {"name": "jitter", "params": {"sigma_px": 40}, "label": "jitter40"}],
            "settings": ["baseline", "gt_start"],
            "optional_suites": [str(tmp_path / "not-here")],
        },
    )
    code, out = run_here(config)
    assert code == 0, out
    assert "not-here is not here; its tasks are skipped" in " ".join(out.split())
    report = (tmp_path / "run" / "report.md").read_text()  # the run prints, and keeps, the drag table
    assert report.startswith("# ScratchWorld single-step drag report") and "## Table 2" in out
    store = RunStore(tmp_path / "run")
    jobs = store.read_table("jobs").to_pylist()
    drags = store.read_table("drags").to_pylist()
    assert len(jobs) == len(drags) == 8
    oracle = [row for row in drags if row["agent"] == "oracle"]
    assert len(oracle) == 4 and all(row["connected"] and row["start_in_region"] for row in oracle)
    for row in drags:
        assert (tmp_path / "run" / row["annotated"]).is_file()
        assert row["setting"] in {"baseline", "gt_start"} and row["drag_type"] in {"T1", "T2"}
        assert (row["gt_start_x"] is not None) == (row["setting"] == "gt_start")
        regions = DragRegions.model_validate_json(row["regions_json"])  # kept with the row, as the metrics saw them
        assert (regions.start.area, regions.end.area) == (row["start_area"], row["end_area"])
        assert regions.fixed_start == (row["fixed_start_x"], row["fixed_start_y"])
        assert regions.start.contains(row["start_x"], row["start_y"]) == row["start_in_region"]
    code, out = run_here(config)
    assert code == 0, out
    assert "8 already decided, 0 to run" in " ".join(out.split())
    assert len(store.read_table("jobs").to_pylist()) == 8
