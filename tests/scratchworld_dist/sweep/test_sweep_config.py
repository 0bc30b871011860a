"""The sweep config: defaults, path resolution, overrides, and every bad input named by its field."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
import yaml

from scratchworld_dist._errors import ConfigError
from scratchworld_dist.kinds.tasks import EpisodeSweep, episode_settings
from scratchworld_dist.sweep import ModelConfig, SweepConfig, load_sweep_config
from tests.conftest import REPO
from workers.contract import ModelSpec


@pytest.fixture(autouse=True)
def _no_ray_address(monkeypatch: pytest.MonkeyPatch) -> None:
    """The developer's own RAY_ADDRESS must not leak into the config under test."""
    monkeypatch.delenv("RAY_ADDRESS", raising=False)


def write(tmp_path: Path, config: Any, name: str = "sweep.yaml") -> Path:
    path = tmp_path / name
    path.write_text(yaml.safe_dump(config), encoding="utf-8")
    return path


def minimal(**fields: Any) -> dict[str, Any]:
    config: dict[str, Any] = {"name": "smoke", "suite": "/suites/ours"}
    config.update(fields)
    return config


def config_error(tmp_path: Path, config: Any) -> str:
    path = write(tmp_path, config)
    with pytest.raises(ConfigError) as caught:
        load_sweep_config(path)
    message = str(caught.value)
    assert str(path) in message, "the error must name the config file"
    return message


# --- valid configs -------------------------------------------------------------------------


def test_minimal_config_and_defaults(tmp_path: Path) -> None:
    config = load_sweep_config(write(tmp_path, minimal()))
    assert config.name == "smoke"
    assert config.suite == Path("/suites/ours")
    assert config.agent.name == "oracle"
    assert config.models == []
    assert config.seeds == [0]
    assert episode_settings(config) == EpisodeSweep()  # the file has no episodes section: its defaults
    assert episode_settings(config).modes == ["composite"] and episode_settings(config).max_steps == 50
    assert config.tasks.categories == [] and config.tasks.ids == [] and config.tasks.task_list is None
    assert config.limits.episode_timeout_s == 900.0
    assert config.limits.retries == 2
    assert config.limits.pages_per_worker is None  # derived from the browser slots at run time
    assert config.limits.browser_slots is None and config.limits.max_in_flight is None
    assert config.output is None
    assert config.run_dir() == Path("results") / "smoke"
    assert config.ray.address is None
    assert episode_settings(config).synthetic is None and episode_settings(config).memory is None


def test_full_config_keeps_every_field(tmp_path: Path) -> None:
    config = load_sweep_config(
        write(
            tmp_path,
            minimal(
                agent="llm",
                models=[
                    {"model": "openai/gpt-4o", "temperature": 0.2, "max_tokens": 512, "api_key_env": "OPENAI_API_KEY"},
                    {"model": "openai/gpt-4o", "name": "gpt-4o-hot", "temperature": 1.0, "params": {"top_p": 0.9}},
                ],
                episodes={"modes": ["primitive", "composite"], "max_steps": 7},
                tasks={"categories": ["debug"], "ids": ["quiz_score"]},
                limits={"episode_timeout_s": 60, "retries": 0, "pages_per_worker": 3, "max_in_flight": 5},
                output="/runs/smoke",
                ray={"address": "10.1.2.3:6379"},
            ),
        )
    )
    assert config.agent.name == "llm"
    assert episode_settings(config).modes == ["primitive", "composite"]
    assert config.tasks.categories == ["debug"] and config.tasks.ids == ["quiz_score"]
    assert episode_settings(config).max_steps == 7
    assert (config.limits.episode_timeout_s, config.limits.retries) == (60.0, 0)
    assert (config.limits.pages_per_worker, config.limits.max_in_flight) == (3, 5)
    assert config.output == Path("/runs/smoke")
    assert config.run_dir() == Path("/runs/smoke")
    assert config.ray.address == "10.1.2.3:6379"
    assert config.model_specs() == [
        ModelSpec(
            name="openai/gpt-4o", model="openai/gpt-4o", temperature=0.2, max_tokens=512, api_key_env="OPENAI_API_KEY"
        ),
        ModelSpec(name="gpt-4o-hot", model="openai/gpt-4o", temperature=1.0, params={"top_p": 0.9}),
    ]


def test_scripted_agents_plan_one_modelless_column(tmp_path: Path) -> None:
    for agent in ("oracle", "noop"):
        config = load_sweep_config(write(tmp_path, minimal(agent=agent)))
        assert config.model_specs() == [None]


def test_seeds_as_a_count_or_a_list(tmp_path: Path) -> None:
    assert load_sweep_config(write(tmp_path, minimal(seeds=3))).seeds == [0, 1, 2]
    assert load_sweep_config(write(tmp_path, minimal(seeds=1))).seeds == [0]
    assert load_sweep_config(write(tmp_path, minimal(seeds=[7, 3]))).seeds == [7, 3]


@pytest.mark.parametrize(
    ("fields", "field"),
    [
        ({"seeds": [1, 2, 1]}, "seeds"),
        ({"seeds": 0}, "seeds"),
        ({"seeds": []}, "seeds"),
        ({"episodes": {"modes": ["composite", "composite"]}}, "episodes.modes"),
        ({"episodes": {"modes": []}}, "episodes.modes"),
    ],
)
def test_duplicate_or_empty_seeds_and_modes_are_refused(tmp_path: Path, fields: dict[str, Any], field: str) -> None:
    message = config_error(tmp_path, minimal(**fields))
    assert f"{field}: " in message


# --- bad input: each names its field -----------------------------------------------------------


@pytest.mark.parametrize(
    ("fields", "expected"),
    [
        ({"nmae": "x"}, ["nmae: unknown key; did you mean 'name'?"]),
        ({"limits": {"retry": 3}}, ["limits.retry: unknown key; did you mean 'retries'?"]),
        ({"episodes": {"max_steps": "many"}}, ["episodes.max_steps: ", "integer"]),
        (
            {"episodes": {"max_steps": {"composite": 0}}},
            ["episodes.max_steps: ", "the step limit of composite must be a positive integer"],
        ),
        ({"episodes": {"max_steps": {"gui": 5}}}, ["episodes.max_steps: ", "unknown mode gui"]),
        (
            {"episodes": {"modes": ["composite", "primitive"], "max_steps": {"composite": 5}}},
            ["episodes: ", "no limit for mode primitive"],
        ),
        ({"episodes": {"maxsteps": 5}}, ["episodes.maxsteps: unknown key; did you mean 'max_steps'?"]),
        ({"episodes": [50]}, ["episodes: ", "dictionary"]),
        ({"primitive": {"ocr": "tesseract"}}, ["primitive.ocr: "]),
        ({"limits": {"episode_timeout_s": "soon"}}, ["limits.episode_timeout_s: ", "number"]),
        ({"limits": {"retries": -1}}, ["limits.retries: ", "greater than or equal to 0"]),
        (
            {"agent": "gpt"},
            [
                "agent: ",
                "agent 'gpt' is not registered for the tasks benchmark (registered: awm, human, llm, noop, oracle",
            ],
        ),
        ({"episodes": {"modes": ["mixed"]}}, ["episodes.modes.0: "]),
        ({"name": "has space"}, ["name: ", "pattern"]),
        ({"tasks": {"categories": ["games"]}}, ["tasks.categories.0: "]),
        ({"models": [{"name": "no model string"}]}, ["models.0.model: Field required"]),
        ({"models": [{"model": "m", "temperature": -1}]}, ["models.0.temperature: "]),
        ({"models": [{"model": "m", "params": {"api_key": "abc"}}]}, ["models.0.params: ", "api_key", "api_key_env"]),
        ({"models": [{"model": "m", "params": {"Token": "abc"}}]}, ["models.0.params: ", "Token"]),
        ({"models": [{"model": "m", "api_key_env": "sk-abc-123"}]}, ["models.0.api_key_env: ", "NAME"]),
        ({"agent": "llm"}, ["an agent that needs a model needs at least one entry under models"]),
    ],
)
def test_bad_field_is_named(tmp_path: Path, fields: dict[str, Any], expected: list[str]) -> None:
    message = config_error(tmp_path, minimal(**fields))
    for part in expected:
        assert part in message


def test_name_and_suite_are_required(tmp_path: Path) -> None:
    message = config_error(tmp_path, {"agent": "noop"})
    assert "name: Field required" in message
    assert "suite: Field required" in message


def test_every_problem_is_listed_at_once(tmp_path: Path) -> None:
    message = config_error(tmp_path, minimal(agent="gpt", episodes={"max_steps": 0}, limits={"retries": "x"}))
    assert "agent: " in message
    assert "episodes.max_steps: " in message
    assert "limits.retries: " in message


def test_duplicate_model_names_are_refused(tmp_path: Path) -> None:
    models = [{"model": "openai/gpt-4o", "temperature": 0}, {"model": "openai/gpt-4o", "temperature": 1}]
    message = config_error(tmp_path, minimal(agent="llm", models=models))
    assert "model names must be distinct" in message
    assert "openai/gpt-4o" in message
    # Naming one of them resolves the clash.
    models[1]["name"] = "gpt-4o-hot"
    assert len(load_sweep_config(write(tmp_path, minimal(agent="llm", models=models))).models) == 2


def test_models_differing_only_in_label_are_refused(tmp_path: Path) -> None:
    models = [
        {"model": "openai/gpt-4o", "name": "a", "api_key_env": "KEY_A"},
        {"model": "openai/gpt-4o", "name": "b", "api_key_env": "KEY_B"},
    ]
    message = config_error(tmp_path, minimal(agent="llm", models=models))
    assert "identical settings" in message
    models[1]["temperature"] = 0.5
    assert len(load_sweep_config(write(tmp_path, minimal(agent="llm", models=models))).models) == 2


def test_secrets_do_not_echo_into_the_error(tmp_path: Path) -> None:
    params_secret = config_error(tmp_path, minimal(models=[{"model": "m", "params": {"api_key": "sk-live-9f8e7d"}}]))
    assert "sk-live-9f8e7d" not in params_secret
    env_secret = config_error(tmp_path, minimal(models=[{"model": "m", "api_key_env": "sk-abc-123"}]))
    assert "sk-abc-123" not in env_secret


def test_malformed_yaml(tmp_path: Path) -> None:
    path = tmp_path / "sweep.yaml"
    path.write_text("name: smoke\nsuite: [unclosed\n", encoding="utf-8")
    with pytest.raises(ConfigError, match="not valid YAML") as caught:
        load_sweep_config(path)
    assert str(path) in str(caught.value)


@pytest.mark.parametrize("text", ["- name: smoke\n- suite: x\n", "", "just a string\n"])
def test_config_must_be_a_mapping(tmp_path: Path, text: str) -> None:
    path = tmp_path / "sweep.yaml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ConfigError, match="must be a mapping") as caught:
        load_sweep_config(path)
    assert str(path) in str(caught.value)


def test_missing_file(tmp_path: Path) -> None:
    path = tmp_path / "nowhere.yaml"
    with pytest.raises(ConfigError, match="cannot read the config") as caught:
        load_sweep_config(path)
    assert str(path) in str(caught.value)


# --- paths, overrides, environment -------------------------------------------------------------


def test_relative_paths_resolve_against_the_config_folder(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    folder = tmp_path / "configs" / "nightly"
    folder.mkdir(parents=True)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    config = load_sweep_config(write(folder, minimal(suite="../../tasks", output="runs/n1")))
    assert config.suite == (tmp_path / "tasks").resolve()
    assert config.output == (folder / "runs" / "n1").resolve()
    assert config.run_dir() == config.output


def test_absolute_paths_are_kept(tmp_path: Path) -> None:
    suite, output = tmp_path / "suite", tmp_path / "out"
    config = load_sweep_config(write(tmp_path, minimal(suite=str(suite), output=str(output))))
    assert (config.suite, config.output) == (suite, output)


def test_output_override_wins_and_is_not_rebased(tmp_path: Path) -> None:
    folder = tmp_path / "configs"
    folder.mkdir()
    path = write(folder, minimal(output="runs/from-file"))
    assert load_sweep_config(path, {"output": tmp_path / "cli-out"}).output == tmp_path / "cli-out"
    # A relative --out means the working directory, as on any command line, not the config's folder.
    assert load_sweep_config(path, {"output": Path("cli-out")}).output == Path("cli-out")


def test_ray_address_override(tmp_path: Path) -> None:
    path = write(tmp_path, minimal(ray={"address": "file-host:6379"}))
    assert load_sweep_config(path).ray.address == "file-host:6379"
    assert load_sweep_config(path, {"ray": {"address": "cli-host:6379"}}).ray.address == "cli-host:6379"


def test_overrides_are_validated_too(tmp_path: Path) -> None:
    path = write(tmp_path, minimal())
    with pytest.raises(ConfigError, match=r"ray\.port: unknown key"):
        load_sweep_config(path, {"ray": {"port": 1}})


def test_ray_address_env_fills_only_an_unset_address(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("RAY_ADDRESS", "env-host:6379")
    assert load_sweep_config(write(tmp_path, minimal())).ray.address == "env-host:6379"
    pinned = write(tmp_path, minimal(ray={"address": "file-host:6379"}), name="pinned.yaml")
    assert load_sweep_config(pinned).ray.address == "file-host:6379"
    assert load_sweep_config(write(tmp_path, minimal()), {"ray": {"address": "auto"}}).ray.address == "auto"


def test_api_key_value_never_enters_the_config(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    secret = "sk-test-5b0d1c2e3f4a"
    monkeypatch.setenv("SCRATCHWORLD_TEST_KEY", secret)
    config = load_sweep_config(
        write(
            tmp_path, minimal(agent="llm", models=[{"model": "openai/gpt-4o", "api_key_env": "SCRATCHWORLD_TEST_KEY"}])
        )
    )
    dumped = config.model_dump(mode="json")
    assert dumped["models"][0]["api_key_env"] == "SCRATCHWORLD_TEST_KEY"
    assert secret not in repr(dumped)
    assert secret not in config.model_dump_json()
    assert secret not in repr(config.model_specs())


def test_model_config_spec_defaults_its_name() -> None:
    spec = ModelConfig(model="anthropic/claude").spec()
    assert spec.name == "anthropic/claude"
    assert ModelConfig(model="anthropic/claude", name="claude").spec().name == "claude"


def test_sweep_config_can_be_built_without_a_file() -> None:
    config = SweepConfig(name="direct", suite=Path("relative/suite"), seeds=2)  # type: ignore[arg-type]
    assert config.seeds == [0, 1]
    assert config.suite == Path("relative/suite")  # only load_sweep_config knows a base folder


# --- the configs we ship --------------------------------------------------------------------

SHIPPED = sorted(p for p in (REPO / "configs").rglob("*.yaml") if p.parent.name != "audit")  # audit/: declarations


@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: p.stem)
def test_every_shipped_config_loads_and_points_at_our_suite(path: Path) -> None:
    config = load_sweep_config(path)
    marker = {"drag": "drag-suite.json", "perception": "perception-suite.json"}.get(config.benchmark, "create")
    assert (config.suite / marker).exists(), "relative suite paths resolve against the config's folder"
    for model in config.models:
        assert model.api_key_env is None or model.api_key_env.isupper()
        assert model.api_base is None, "endpoints come from the environment, never from a shipped file"


def test_local_llm_config_reads_endpoint_and_key_from_the_environment() -> None:
    config = load_sweep_config(REPO / "configs" / "local-llm.yaml")
    (model,) = config.model_specs()
    assert model is not None and config.agent.name == "llm" and episode_settings(config).modes == ["composite"]
    assert (model.model, model.api_base_env, model.api_key_env) == (
        "openai/local",
        "SCRATCHWORLD_LLM_BASE_URL",
        "SCRATCHWORLD_LLM_API_KEY",
    )


def test_llm_settings_and_model_pacing_are_validated(tmp_path: Path) -> None:
    model = {"model": "openai/x", "api_base": "http://h/v1", "api_base_env": "X_URL"}
    assert "api_base or api_base_env" in config_error(tmp_path, minimal(agent="llm", models=[model]))
    model = {"model": "openai/x", "api_base_env": "http://h/v1"}
    assert "models.0.api_base_env" in config_error(tmp_path, minimal(agent="llm", models=[model]))
    model = {"model": "openai/x", "coordinates": "inches"}
    assert "models.0.coordinates" in config_error(tmp_path, minimal(agent="llm", models=[model]))
    model = {"model": "openai/x", "rate_limits": {"requests_per_minute": 0}}
    assert "models.0.rate_limits.requests_per_minute" in config_error(tmp_path, minimal(agent="llm", models=[model]))
    bad_history = minimal(agent="llm", models=[{"model": "openai/x"}], llm={"history_messages": 0})
    assert "llm.history_messages" in config_error(tmp_path, bad_history)
    assert "limits.budget_usd" in config_error(tmp_path, minimal(limits={"budget_usd": -1}))
