"""The Python API: a sweep run from Python with keyword overrides, its results as tables (journal rows
included, effective attempts by default), its report as the data ``report --format json`` writes, and the
report schemas published in docs/schemas."""

from __future__ import annotations

import json
from pathlib import Path

import jsonschema
import pytest

from scratchworld_dist import api
from scratchworld_dist._errors import ConfigError, NotARunDirError
from scratchworld_dist.kinds.tasks.report import RunReport
from scratchworld_dist.reports import report_schemas
from scratchworld_dist.results import JobRecord, RunStore
from tests.conftest import REPO
from tests.support.cli_runner import invoke
from tests.support.run_dirs import job, make_run

DEMO = REPO / "configs" / "demo.yaml"
TASKS = ["countdown_launch", "sum_two_numbers"]


@pytest.mark.ray
def test_a_sweep_runs_from_python_and_reads_back_as_tables_and_report(tmp_path: Path, shared_ray: int) -> None:
    out = tmp_path / "run"
    result = api.run(DEMO, tasks__ids=TASKS, episodes__modes=["composite"], output=str(out))
    assert (result.run_dir, result.planned, result.outcomes["passed"]) == (out, 2, 2)
    assert isinstance(result.report, RunReport) and result.report.rows[0].sr == 1.0

    written = json.loads(invoke("report", str(out), "--format", "json").stdout)
    assert api.report([out]).model_dump(mode="json") == written  # the same data as the CLI's JSON
    jsonschema.validate(written, report_schemas()["tasks-report.schema.json"])

    (passed,) = [row for row in api.load_results(out).to_pylist() if row["task_id"] == TASKS[0]]
    store = RunStore(out)
    store.open_for_writing()  # a later error attempt of a passed job, left in the journal (not compacted)
    store.commit(JobRecord(job=job(passed["job_id"], "error", attempt=9, task_id=TASKS[0], run_name="demo")))
    every = api.load_results(out, effective=False)
    assert every.num_rows == 3 and 9 in every.column("attempt").to_pylist()  # journal rows are read too
    counted = api.load_results(out, as_="pandas")
    assert len(counted) == 2 and set(counted["outcome"]) == {"passed"}  # a verdict outranks a later error
    steps = api.load_results(out, "steps", as_="polars")
    assert steps.height > 0 and set(steps["job_id"]) == set(counted["job_id"])
    store.close()
    assert api.plan(DEMO, tasks__ids=TASKS, modes=["composite"], output=str(out)).to_run == 0  # the former key too


def test_keyword_overrides_are_checked_like_the_file(tmp_path: Path) -> None:
    with pytest.raises(ConfigError, match=r"tasks\.limit: Input should be greater than 0"):
        api.sweep_config(DEMO, tasks__limit=0)
    config = api.sweep_config(DEMO, limits__retries=5, seeds=[3])
    assert (config.limits.retries, config.seeds) == (5, [3])
    assert api.sweep_config(config, seeds=2).seeds == [0, 1]  # a config object takes overrides too
    with pytest.raises(ValueError, match="no table 'nonesuch': tables are jobs, steps, tests"):
        api.load_results(tmp_path, "nonesuch")


def test_the_published_report_schemas_are_current() -> None:
    published = REPO / "docs" / "schemas"
    for name, schema in report_schemas().items():
        assert json.loads((published / name).read_text()) == schema, f"run: scratchworld schemas docs/schemas ({name})"


def test_the_api_says_no_to_folders_that_are_no_run_and_to_unknown_formats(tmp_path: Path) -> None:
    empty = tmp_path / "empty"
    empty.mkdir()
    for folder, why in ((tmp_path / "missing", "no such folder"), (empty, "no manifest.json in it")):
        with pytest.raises(NotARunDirError, match=why):
            api.load_results(folder)  # never an empty table
        with pytest.raises(NotARunDirError, match=why):
            api.report(folder)
    run = make_run(tmp_path / "run", [job("a"), job("b", "failed")], planned=2, tasks=2)
    with pytest.raises(ValueError, match="as_='arrow': choose one of pyarrow, pandas, polars"):
        api.load_results(run, as_="arrow")  # type: ignore[call-overload]
    with pytest.raises(ValueError, match="no table 'job'"):
        api.load_results(run, "job")


def test_one_run_directory_is_taken_alone_or_in_a_list(tmp_path: Path) -> None:
    run = make_run(tmp_path / "run", [job("a"), job("b", "failed")], planned=2, tasks=2)
    alone, listed = api.report(str(run)), api.report([run])
    assert isinstance(alone, RunReport) and alone.model_dump() == listed.model_dump()
    assert api.run_dir_list(run) == api.run_dir_list(str(run)) == [run]
    assert api.load_results(str(run)).num_rows == 2
    assert type(api.load_results(run, as_="pandas")).__name__ == "DataFrame"
