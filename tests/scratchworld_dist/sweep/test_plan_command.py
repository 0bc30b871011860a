"""``scratchworld plan`` and the overrides ``run`` shares with it: checked like the file, applied before planning,
and a preview that counts what the run directory already decided and what the rest may cost."""

from __future__ import annotations

import hashlib
from pathlib import Path
from typing import Any

import pytest
import yaml

from scratchworld_dist._errors import ConfigError
from scratchworld_dist._plan_preview import preview_plan
from scratchworld_dist._sweep_manifest import checked_manifest
from scratchworld_dist.kinds.tasks import episode_settings
from scratchworld_dist.results import JobRecord, RunStore, write_manifest
from scratchworld_dist.sweep import SweepOverrides, load_sweep_config, plan_run
from tests.conftest import SUITE_DIR
from tests.support.cli_runner import invoke
from tests.support.run_dirs import job

MODEL = {"model": "openai/scripted", "name": "scripted", "api_base": "http://127.0.0.1:9/v1"}


def write(tmp_path: Path, episodes: dict[str, Any] | None = None, **fields: Any) -> Path:
    path = tmp_path / "sweep.yaml"
    config = {"name": "preview", "suite": str(SUITE_DIR), "agent": "llm", "models": [MODEL]}
    config["episodes"] = {"max_steps": 7, **(episodes or {})}
    path.write_text(yaml.safe_dump({**config, "output": str(tmp_path / "run"), **fields}))
    return path


def tree(root: Path) -> dict[str, str]:
    """Every file and folder under ``root``, a file by its bytes' digest (a folder by its name only)."""
    return {
        str(path.relative_to(root)): hashlib.sha256(path.read_bytes()).hexdigest() if path.is_file() else "folder"
        for path in root.rglob("*")
    }


def test_each_override_fails_as_the_same_field_in_the_file_would(tmp_path: Path) -> None:
    cases = [
        (SweepOverrides(limit=0), {"tasks": {"limit": 0}}),
        (SweepOverrides(settings=["limits.retries=-1"]), {"limits": {"retries": -1}}),
        (SweepOverrides(modes=["composite,gui"]), {"episodes": {"modes": ["composite", "gui"]}}),
        (SweepOverrides(settings=["max_steps=0"]), {"episodes": {"max_steps": 0}}),  # a former key's old spelling
        (SweepOverrides(seeds="0,0"), {"seeds": [0, 0]}),
        (SweepOverrides(settings=["drag.types=[T9]"]), {"drag": {"types": ["T9"]}}),
    ]
    for overrides, in_file in cases:
        with pytest.raises(ConfigError) as by_flag:
            load_sweep_config(write(tmp_path), changes=overrides)
        with pytest.raises(ConfigError) as by_file:
            load_sweep_config(write(tmp_path, **in_file))
        assert str(by_flag.value) == str(by_file.value), overrides


def test_overrides_change_the_config_a_run_records(tmp_path: Path) -> None:
    overrides = SweepOverrides(
        models=["scripted", "openai/other"], tasks=["countdown_launch,star_shower"], seeds="3", modes=["primitive"],
        settings=["limits.retries=4", "llm.retry.max_attempts=2", "tasks.categories=[create]"],
    )  # fmt: skip
    config = load_sweep_config(write(tmp_path), changes=overrides)
    assert [m.name or m.model for m in config.models] == ["scripted", "openai/other"]
    assert config.models[0].api_base == MODEL["api_base"]  # chosen by name: the file's entry, whole
    assert config.tasks.ids == ["countdown_launch", "star_shower"] and config.tasks.categories == ["create"]
    assert (config.seeds, episode_settings(config).modes, config.limits.retries) == ([0, 1, 2], ["primitive"], 4)
    assert config.llm.retry.max_attempts == 2
    assert config.model_dump(mode="json")["limits"]["retries"] == 4  # what the manifest stores


def test_a_malformed_set_is_one_line_naming_it(tmp_path: Path) -> None:
    for setting, message in [
        ("limits.retries", "--set 'limits.retries': write it as dotted.key=value"),
        ("name.first=x", "--set name.first: name is not a section of the config"),
        ("seeds=[1,", "--set seeds: the value is not valid YAML"),
    ]:
        done = invoke("plan", str(write(tmp_path)), "--set", setting)
        assert done.returncode != 0 and message in done.stderr and len(done.stderr.strip().splitlines()) == 1


def test_limit_keeps_the_first_items_and_only_their_jobs(tmp_path: Path) -> None:
    full = plan_run(load_sweep_config(write(tmp_path)))
    cut = plan_run(load_sweep_config(write(tmp_path), changes=SweepOverrides(limit=2)))
    first = [content.task.id for content in full.contents[:2]]
    assert [content.task.id for content in cut.contents] == first and cut.suite.tasks == 2
    assert [j.job_id for j in cut.jobs] == [j.job_id for j in full.jobs if j.task_id in first]


def test_plan_counts_decided_jobs_calls_and_measures_tokens_in_its_run_directory(tmp_path: Path) -> None:
    config_file = write(tmp_path, episodes={"modes": ["composite", "primitive"]}, seeds=2)
    config = load_sweep_config(config_file)
    plan = plan_run(config)
    jobs = plan.jobs
    composite = [j for j in jobs if j.mode == "composite"]
    config.run_dir().mkdir(parents=True)
    write_manifest(config.run_dir(), checked_manifest(plan, config.run_dir(), force=False))
    store = RunStore(config.run_dir())
    store.open_for_writing()
    for spec, outcome in zip(composite[:3], ["passed", "failed", "error"], strict=True):
        row = job(spec.job_id, outcome, model="scripted", agent="llm", mode="composite", steps=4, input_tokens=400)
        store.commit(JobRecord(job=row))
    store.close()
    written = tree(tmp_path / "run")
    preview = preview_plan(config)
    lines = {line.mode: line for line in preview.lines}
    per_mode = len(jobs) // 2
    assert (lines["composite"].decided, lines["composite"].to_run) == (2, per_mode - 2)  # an error is not decided
    retries = config.limits.retries
    assert lines["composite"].model_calls == 7 * (per_mode - 2) * (1 + retries)  # step budgets, every retry
    measured = lines["composite"].cost.rates
    assert measured is not None and measured.source.startswith("measured: 3 composite attempt(s), scripted's")
    assert (measured.input_per_step, measured.steps_per_attempt) == (100, 4)  # 400 tokens over 4 steps
    assert lines["composite"].cost.input_tokens == 100 * 4 * (per_mode - 2)  # one attempt per job measured
    assert lines["primitive"].cost.rates is not None and lines["primitive"].cost.rates.source.startswith("default")
    assert lines["composite"].cost.cost_usd is None  # LiteLLM prices no openai/scripted: unknown, and said so
    done = invoke("plan", str(config_file))
    assert done.returncode == 0, done.stderr
    total_calls = 7 * (len(jobs) - 2) * (1 + retries)
    assert f"{len(jobs) - 2} job(s) to run, 2 already decided; at most {total_calls} model call(s)" in done.stdout
    assert "estimated cost unknown for" in done.stdout and "LiteLLM has no price for openai/scripted" in done.stdout
    assert tree(tmp_path / "run") == written  # planning wrote nothing: no file added, changed or removed
