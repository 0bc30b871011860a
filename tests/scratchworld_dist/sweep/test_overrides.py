"""The command line's changes keep a config's meaning: ``--model`` keeps the config's entry (and a model it does not
name takes LiteLLM's defaults, said, never another entry's endpoint or key), ``-M`` sets model settings, ``--set``
reaches list items, ``--limit`` samples at random when asked, ``--tag`` labels the run without changing it."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
import yaml

from scratchworld_dist._errors import ConfigError
from scratchworld_dist._sweep_manifest import checked_manifest, config_hash
from scratchworld_dist.results import write_manifest
from scratchworld_dist.sweep import SweepOverrides, load_sweep_config, plan_run
from tests.conftest import SUITE_DIR
from tests.support.cli_runner import invoke

LOCAL = {
    "model": "openai/local", "name": "local", "api_base_env": "SCRATCHWORLD_LLM_BASE_URL",
    "api_key_env": "SCRATCHWORLD_LLM_API_KEY", "temperature": 0, "max_tokens": 2048,
}  # fmt: skip


def write(tmp_path: Path, **fields: Any) -> Path:
    path = tmp_path / "sweep.yaml"
    config = {"name": "overrides", "suite": str(SUITE_DIR), "agent": "llm", "models": [LOCAL]}
    path.write_text(yaml.safe_dump({**config, "output": str(tmp_path / "run"), **fields}))
    return path


def test_model_keeps_its_entry_and_a_new_model_takes_no_other_entrys_settings(tmp_path: Path) -> None:
    said: list[str] = []
    config = load_sweep_config(write(tmp_path), changes=SweepOverrides(models=["local"]), notice=said.append)
    assert config.models[0].model_dump(exclude_none=True, exclude_defaults=True) == LOCAL and said == []
    config = load_sweep_config(
        write(tmp_path), changes=SweepOverrides(models=["openai/gpt-4o-mini"]), notice=said.append
    )
    (new,) = config.models
    assert new.model_dump(exclude_defaults=True) == {"model": "openai/gpt-4o-mini"}  # no endpoint, key, sampling
    assert said == [
        "notice: model openai/gpt-4o-mini is not in the config; it runs with LiteLLM's defaults: the provider's "
        "temperature and max_tokens, LiteLLM's endpoint and key variable for its provider, no api_key_env (so no "
        "probe unless --probe); set any of them with -M openai/gpt-4o-mini:key=value"
    ]
    done = invoke("plan", str(write(tmp_path)), "--model", "openai/gpt-4o-mini", "--limit", "1")
    assert done.returncode == 0, done.stderr
    assert "notice: model openai/gpt-4o-mini is not in the config" in done.stderr
    assert (
        "model openai/gpt-4o-mini (openai/gpt-4o-mini): temperature provider default, max_tokens provider default, "
        "endpoint LiteLLM's default for its provider, key LiteLLM's variable for its provider, probe off"
    ) in done.stdout
    kept = invoke("plan", str(write(tmp_path)), "--model", "local", "--limit", "1")
    assert (
        "model local (openai/local): temperature 0.0, max_tokens 2048, endpoint $SCRATCHWORLD_LLM_BASE_URL, "
        "key $SCRATCHWORLD_LLM_API_KEY, probe on, no LiteLLM price"
    ) in kept.stdout


def test_model_args_set_every_model_or_one_a_field_or_a_param(tmp_path: Path) -> None:
    other = {"model": "ollama/llama3:8b", "api_base": "http://127.0.0.1:9"}
    path = write(tmp_path, models=[LOCAL, other])
    args = ["temperature=0.5", "ollama/llama3:8b:max_tokens=64", "local:top_p=0.9", "rate_limits.requests_per_minute=5"]
    config = load_sweep_config(path, changes=SweepOverrides(model_args=args))
    local, llama = config.models
    assert (local.temperature, local.max_tokens, local.params) == (0.5, 2048, {"top_p": 0.9})
    assert (llama.temperature, llama.max_tokens, llama.params) == (0.5, 64, {})  # a name with a colon
    assert local.rate_limits is not None and local.rate_limits.requests_per_minute == 5
    by_flag = invoke("plan", str(path), "-M", "local:temperature=0.25", "--limit", "1")
    assert by_flag.returncode == 0 and "model local (openai/local): temperature 0.25," in by_flag.stdout
    for argument, message in [
        ("gpt:temperature=0", "-M gpt:temperature: no model named gpt (the models: local, ollama/llama3:8b)"),
        ("temperature", "-M 'temperature': write it as key=value, or NAME:key=value for one model"),
        ("temperature=-1", "models.0.temperature: Input should be greater than or equal to 0"),
        ("api_key=sk-1", "models.0.params: Value error, api_key may not appear in a config; use api_key_env"),
    ]:
        done = invoke("plan", str(path), "-M", argument)
        assert done.returncode == 2 and message in done.stderr, done.stderr
        assert len(done.stderr.strip().splitlines()) == 1 and "sk-1" not in done.stderr


def test_set_reaches_list_items_by_index(tmp_path: Path) -> None:
    config = load_sweep_config(write(tmp_path), changes=SweepOverrides(settings=["models.0.temperature=0.7"]))
    assert config.models[0].temperature == 0.7 and config.models[0].api_key_env == LOCAL["api_key_env"]
    for setting, message in [
        ("models.1.temperature=0", "--set models.1.temperature: models is a list of 1 item(s); give an index from 0"),
        ("models.x.temperature=0", "--set models.x.temperature: models is a list of 1 item(s)"),
        ("seeds.0.x=1", "--set seeds.0.x: seeds.0 is not a section of the config"),
    ]:
        with pytest.raises(
            ConfigError, match="^" + message.replace(".", r"\.").replace("(", r"\(").replace(")", r"\)")
        ):
            load_sweep_config(write(tmp_path, seeds=[0]), changes=SweepOverrides(settings=[setting]))


def test_plan_warns_when_the_agent_calls_no_model(tmp_path: Path) -> None:
    done = invoke("plan", str(write(tmp_path, agent="oracle")), "--model", "openai/gpt-4o-mini", "--limit", "2")
    assert done.returncode == 0, done.stderr
    assert "warning: agent oracle calls no model: its jobs only carry the models' names" in done.stdout
    assert "at most 0 model call(s)" in done.stdout and "estimated cost $0.0000" in done.stdout
    assert "model openai/gpt-4o-mini (openai/gpt-4o-mini): not called by the agent" in done.stdout


def test_a_random_limit_draws_the_same_items_for_a_seed_in_suite_order(tmp_path: Path) -> None:
    def drawn(seed: int) -> list[str]:
        changes = SweepOverrides(limit=4, sample="random", sample_seed=seed)
        return [content.task.id for content in plan_run(load_sweep_config(write(tmp_path), changes=changes)).contents]

    full = [content.task.id for content in plan_run(load_sweep_config(write(tmp_path))).contents]
    draws = {seed: drawn(seed) for seed in range(4)}
    assert drawn(2) == draws[2]  # deterministic
    assert len({tuple(items) for items in draws.values()}) > 1  # the seed matters
    for items in draws.values():
        assert len(items) == 4 and items == [task for task in full if task in items]  # suite order
    assert any(items != full[:4] for items in draws.values())  # not the first four
    plan = plan_run(load_sweep_config(write(tmp_path), changes=SweepOverrides(limit=4, sample="random")))
    assert {job.task_id for job in plan.jobs} == set(draws[0]) and plan.suite.tasks == 4  # default seed 0
    done = invoke("plan", str(write(tmp_path)), "--sample", "random")
    assert done.returncode == 2 and "tasks: Value error, sample random draws tasks.limit items" in done.stderr


def test_tags_label_the_run_without_changing_it(tmp_path: Path) -> None:
    plain = load_sweep_config(write(tmp_path, tags={"team": "evals"}))
    tagged = load_sweep_config(write(tmp_path, tags={"team": "evals"}), changes=SweepOverrides(tags=["ticket=52"]))
    assert tagged.tags == {"team": "evals", "ticket": "52"} and config_hash(plain) == config_hash(tagged)
    with pytest.raises(ConfigError, match="--tag 'ticket': write it as key=value"):
        load_sweep_config(write(tmp_path), changes=SweepOverrides(tags=["ticket"]))
    run_dir = plain.run_dir()
    run_dir.mkdir(parents=True)
    write_manifest(run_dir, checked_manifest(plan_run(plain), run_dir, force=False))
    resumed = checked_manifest(
        plan_run(load_sweep_config(write(tmp_path), changes=SweepOverrides(tags=["a=b"]))), run_dir, False
    )
    assert resumed.tags == {"team": "evals", "a": "b"}  # a resume adds its tags to those recorded
