"""The model cache on the driver's side: the config and its refusals, job identity, rows, old shards and reports.

The end-to-end sweep (real Ray, Chromium and LiteLLM) is in ``test_llm_sweep.py``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pyarrow as pa
import pyarrow.parquet as pq
import pytest
import yaml

from scratchworld_dist._errors import ConfigError
from scratchworld_dist.kinds.tasks import EpisodeBody, EpisodeMatrix, plan_jobs, read_task
from scratchworld_dist.kinds.tasks.report import build_report, render_html, render_markdown
from scratchworld_dist.results import RunStore, record_of, table_schema
from scratchworld_dist.suites import load_suite
from scratchworld_dist.sweep import JobSpec, load_sweep_config, worker_job
from tests.conftest import SUITE_DIR
from tests.support.run_dirs import job, make_run
from workers.contract import AgentRef, JobResult, ModelCacheSettings, ModelSpec, StepRecord

UNSEEDED = "anthropic/claude-3-5-sonnet-20240620"
"""LiteLLM sends Anthropic models no seed."""


@pytest.fixture(autouse=True)
def _no_ray_address(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("RAY_ADDRESS", raising=False)


def config_file(folder: Path, **fields: Any) -> Path:
    config: dict[str, Any] = {
        "name": "cached",
        "suite": "/suites/ours",
        "agent": "llm",
        "models": [{"model": "openai/gpt-4o", "temperature": 0}],
        "model_cache": {"dir": "cache"},
    }
    config.update(fields)
    path = folder / "sweep.yaml"
    path.write_text(yaml.safe_dump(config), encoding="utf-8")
    return path


def refusal(path: Path) -> str:
    with pytest.raises(ConfigError) as caught:
        load_sweep_config(path)
    message = str(caught.value)
    assert "\n" not in message and str(path) in message
    return message


# -- config ----------------------------------------------------------------------------------


def test_the_cache_is_off_by_default_and_its_folder_resolves_against_the_config(tmp_path: Path) -> None:
    folder = tmp_path / "configs"
    folder.mkdir()
    assert load_sweep_config(config_file(folder, model_cache=None)).model_cache is None
    assert load_sweep_config(config_file(folder)).model_cache == ModelCacheSettings(dir=(folder / "cache").resolve())
    absolute = tmp_path / "shared" / "cache"
    assert load_sweep_config(config_file(folder, model_cache={"dir": str(absolute)})).model_cache.dir == absolute  # type: ignore[union-attr]
    # --model-cache (given absolute by the command line) replaces the file's folder.
    override = load_sweep_config(config_file(folder), {"model_cache": {"dir": str(absolute)}})
    assert override.model_cache == ModelCacheSettings(dir=absolute)


def test_a_cache_section_with_other_fields_is_refused(tmp_path: Path) -> None:
    message = refusal(config_file(tmp_path, model_cache={"dir": "c", "ttl": 5}))
    assert "model_cache.ttl" in message


@pytest.mark.parametrize(
    ("model", "said"),
    [
        ({"model": UNSEEDED, "temperature": 0.7}, "temperature 0.7"),
        ({"model": UNSEEDED}, "temperature unset"),
        ({"model": UNSEEDED, "params": {"temperature": 1.0}}, "temperature 1.0"),
    ],
)
def test_sampling_a_model_that_takes_no_seed_is_refused_for_caching(
    tmp_path: Path, model: dict[str, Any], said: str
) -> None:
    message = refusal(config_file(tmp_path, models=[{"name": "claude", **model}]))
    assert f"model_cache: Value error, model claude: {said}" in message and f"{UNSEEDED} takes no seed" in message
    assert "set temperature: 0 or turn model_cache off" in message
    # The same model is fine without the cache, and at temperature 0 with it.
    load_sweep_config(config_file(tmp_path, models=[{"name": "claude", **model}], model_cache=None))
    load_sweep_config(config_file(tmp_path, models=[{"model": UNSEEDED, "temperature": 0}]))


def test_a_seeded_model_may_sample_and_be_cached(tmp_path: Path) -> None:
    config = load_sweep_config(config_file(tmp_path, models=[{"model": "openai/gpt-4o", "temperature": 0.8}]))
    assert config.model_cache is not None


def test_an_agents_other_models_are_checked_too(tmp_path: Path) -> None:
    agent = {"name": "planner_grounder", "params": {"grounder": {"name": "pointer", "model": UNSEEDED}}}
    message = refusal(config_file(tmp_path, agent=agent, episodes={"modes": ["primitive"]}))
    assert "model pointer: temperature unset" in message


# -- identity --------------------------------------------------------------------------------


def test_the_cache_changes_no_job_id_and_reaches_every_episode() -> None:
    suite = load_suite(SUITE_DIR)
    contents = [read_task(task) for task in suite.tasks[:2]]
    model = ModelSpec(name="m", model="openai/gpt-4o", temperature=0)
    cache = ModelCacheSettings(dir=Path("/shared/cache"))
    plain = list(
        plan_jobs(
            EpisodeMatrix(
                models=[model],
                modes=["composite"],
                agent=AgentRef(name="llm"),
                tasks=contents,
                seeds=[0, 1],
                max_steps=10,
                harness="h",
            )
        )
    )
    cached = list(
        plan_jobs(
            EpisodeMatrix(
                models=[model],
                modes=["composite"],
                agent=AgentRef(name="llm"),
                tasks=contents,
                seeds=[0, 1],
                max_steps=10,
                harness="h",
                model_cache=cache,
            )
        )
    )
    assert [j.job_id for j in plain] == [j.job_id for j in cached]
    assert {worker_job(j, 1, 60).model_cache for j in cached} == {cache}
    assert {worker_job(j, 1, 60).model_cache for j in plain} == {None}


def test_turning_the_cache_on_keeps_the_run_directorys_config_hash(tmp_path: Path) -> None:
    from scratchworld_dist._sweep_manifest import config_hash

    on = load_sweep_config(config_file(tmp_path))
    off = load_sweep_config(config_file(tmp_path, model_cache=None))
    assert config_hash(on) == config_hash(off)


def test_a_cache_folder_no_one_can_write_is_refused_before_any_job(tmp_path: Path) -> None:
    from scratchworld_dist._run import _open_model_cache

    blocker = tmp_path / "a-file"
    blocker.write_text("")
    with pytest.raises(ConfigError) as caught:
        _open_model_cache(blocker / "cache")
    assert str(caught.value).startswith(f"model_cache.dir: cannot store model replies in {blocker / 'cache'}")
    _open_model_cache(tmp_path / "new" / "cache")
    assert (tmp_path / "new" / "cache").is_dir() and not list((tmp_path / "new" / "cache").iterdir())


# -- rows ------------------------------------------------------------------------------------


def planned(cache: ModelCacheSettings | None) -> JobSpec:
    model = ModelSpec(name="m", model="openai/gpt-4o", temperature=0)
    return JobSpec(
        job_id="j1",
        model=model,
        agent=AgentRef(name="llm"),
        task_id="t1",
        category="create",
        task_hash="0" * 16,
        seed=0,
        harness="h",
        body=EpisodeBody(mode="composite", max_steps=10),
        model_cache=cache,
    )


def result() -> JobResult:
    steps = [
        StepRecord(index=0, action="add_block", ok=True, llm_calls=2, llm_cache_hits=2, input_tokens=10),
        StepRecord(index=1, action="done", ok=True, llm_calls=1, llm_cache_hits=0, cost_usd=0.01),
    ]
    return JobResult(job_id="j1", attempt=1, outcome="failed", stop_reason="done", steps=steps)


def test_rows_record_the_hits_and_null_without_a_cache(tmp_path: Path) -> None:
    with_cache = record_of(
        planned(ModelCacheSettings(dir=tmp_path)), result(), run_name="r", suite_hash="s", artifact_dir=None
    )
    assert (with_cache.job.llm_calls, with_cache.job.llm_cache_hits) == (3, 2)
    assert [s.llm_cache_hits for s in with_cache.steps] == [2, 0]
    without = record_of(planned(None), result(), run_name="r", suite_hash="s", artifact_dir=None)
    assert without.job.llm_cache_hits is None and [s.llm_cache_hits for s in without.steps] == [None, None]

    store = RunStore(tmp_path / "run")
    store.open_for_writing()
    store.commit(with_cache)
    store.close()  # compacted into Parquet shards
    assert [row.llm_cache_hits for row in store.job_rows()] == [2]
    assert store.read_table("steps").column("llm_cache_hits").to_pylist() == [2, 0]


def test_shards_written_before_the_column_existed_still_read(tmp_path: Path) -> None:
    run = tmp_path / "old-run"
    store = RunStore(run)
    store.open_for_writing()
    store.commit(record_of(planned(None), result(), run_name="r", suite_hash="s", artifact_dir=None))
    store.close()
    for table in ("jobs", "steps"):
        shard = run / table / "part-000001.parquet"
        older = pq.read_table(shard).drop_columns(["llm_cache_hits"])
        schema = pa.schema(older.schema, metadata=table_schema(table).metadata)
        pq.write_table(older.cast(schema), shard)
        assert "llm_cache_hits" not in pq.read_schema(shard).names
    (row,) = RunStore(run).job_rows()
    assert row.llm_cache_hits is None and row.llm_calls == 3
    assert RunStore(run).read_table("steps").column("llm_cache_hits").to_pylist() == [None, None]


# -- reports ---------------------------------------------------------------------------------


def test_the_report_shows_cache_hits_only_for_runs_that_used_the_cache(tmp_path: Path) -> None:
    cached = [
        job("a", llm_calls=10, llm_cache_hits=10, cost_usd=0.0),
        job("b", llm_calls=6, llm_cache_hits=2, cost_usd=0.04),
    ]
    report = build_report([make_run(tmp_path / "cached", cached, planned=2, tasks=2)])
    (row,) = report.rows
    assert (row.llm_cache_hits, row.llm_cache_calls) == (12, 16)
    markdown = render_markdown(report)
    assert "| cache hits |" in markdown and "| 12/16 (75.0%) |" in markdown
    assert "Cache hits: model calls answered from the sweep's model cache" in markdown
    assert "12/16 (75.0%)" in render_html(report)

    plain = build_report([make_run(tmp_path / "plain", [job("a"), job("b")], planned=2, tasks=2)])
    assert plain.rows[0].llm_cache_hits is None
    assert "cache hits" not in render_markdown(plain) and "Cache hits" not in render_markdown(plain)
