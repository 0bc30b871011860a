"""The episode kind's settings moved from the top level of a sweep config into ``episodes:``. Configs, overrides
and run manifests written the former way still read: each former key is said once where it lives now, the same
sweep validates to the same config, plans the same jobs and hashes the same in either layout, and an old run
directory reads, views, exports and is told apart by what it holds, not by how its config was laid out."""

from __future__ import annotations

import json
import shutil
from pathlib import Path
from typing import Any

import pytest
import yaml
from pydantic import ValidationError

from scratchworld_dist import api
from scratchworld_dist._errors import ConfigError
from scratchworld_dist._sweep_manifest import _hash_as_now, config_hash
from scratchworld_dist.kinds.tasks import EPISODES_KEY, EpisodeSweep, episode_settings
from scratchworld_dist.kinds.tasks.report._build import jobs_per_group
from scratchworld_dist.results import read_manifest
from scratchworld_dist.sweep import SweepConfig, SweepOverrides, load_sweep_config, moved_keys, plan_run
from scratchworld_dist.viewer import ViewerSite
from tests.conftest import DATA, REPO
from tests.support.cli_runner import invoke
from tests.support.run_dirs import job, make_run
from tests.support.sweep_driver import run_here

DEMO = REPO / "configs" / "demo.yaml"
OLD_RUNS = DATA / "runs_v3"
TASKS = ["sum_two_numbers", "quiz_score"]


def former_layout(data: dict[str, Any]) -> dict[str, Any]:
    """A config's mapping as it was written before ``episodes:`` existed: that section's keys at the top level."""
    old = {key: value for key, value in data.items() if key != EPISODES_KEY}
    return {**old, **data.get(EPISODES_KEY, {})}


def write(path: Path, data: dict[str, Any]) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(yaml.safe_dump(data, sort_keys=False), encoding="utf-8")
    return path


def loaded(path: Path, **changes: Any) -> tuple[SweepConfig, list[str]]:
    """The config at ``path`` and the notices its loading gave."""
    said: list[str] = []
    return load_sweep_config(path, changes=SweepOverrides(**changes), notice=said.append), said


def job_ids(config: SweepConfig) -> list[str]:
    return [job.job_id for job in plan_run(config, notice=lambda _: None).jobs]


def test_the_section_takes_over_exactly_the_former_keys() -> None:
    assert EpisodeSweep.former_keys == tuple(EpisodeSweep.model_fields)
    assert moved_keys() == dict.fromkeys(EpisodeSweep.former_keys, EPISODES_KEY)


def test_the_demo_config_plans_the_jobs_of_its_former_layout(tmp_path: Path) -> None:
    """The demo as shipped (``episodes:``) and as it was written before, in the same places: one config, one job
    matrix, one hash; only the former layout is told where its keys live now."""
    new, new_said = loaded(DEMO)
    shipped = yaml.safe_load(DEMO.read_text())
    assert set(shipped[EPISODES_KEY]) == {"modes", "max_steps"}
    places = {"suite": str(new.suite), "output": str(new.output)}  # its relative paths, resolved as the file has them
    old, old_said = loaded(write(tmp_path / "demo.yaml", former_layout({**shipped, **places})))
    assert new_said == [] and old_said == [
        "notice: modes is now episodes.modes",
        "notice: max_steps is now episodes.max_steps",
    ]
    assert old == new
    assert job_ids(old) == job_ids(new) and len(job_ids(new)) == 24
    assert config_hash(old) == config_hash(new)


SWEEPS = {
    "oracle": {
        "agent": "oracle",
        "episodes": {
            "modes": ["composite", "primitive"],
            "max_steps": {"composite": 9, "primitive": 90},
            "oracle_trajectories": "plans",
            "episode_clock": {"mode": "virtual", "think_ms": 250},
            "synthetic": {"tasks": [TASKS[0]], "duration_s": 0},
        },
    },
    "awm": {
        "agent": "awm",
        "models": [{"model": "openai/gpt-4o-mini", "name": "mini"}],
        "episodes": {"memory": {"kind": "online", "wave_size": 1}, "max_steps": 5},
    },
}


@pytest.mark.parametrize("sweep", list(SWEEPS))
def test_each_former_key_reads_once_with_its_notice_and_plans_the_same_jobs(tmp_path: Path, sweep: str) -> None:
    (tmp_path / "plans").mkdir()
    data = {"name": "moved", "suite": str(REPO / "tasks"), "tasks": {"ids": TASKS}, **SWEEPS[sweep]}
    new, new_said = loaded(write(tmp_path / "new.yaml", data))
    old, old_said = loaded(write(tmp_path / "old.yaml", former_layout(data)))
    moved = list(data[EPISODES_KEY])
    assert new_said == [] and sorted(old_said) == sorted(f"notice: {key} is now episodes.{key}" for key in moved)
    assert old == new and config_hash(old) == config_hash(new)
    assert job_ids(old) == job_ids(new)
    if sweep == "oracle":  # a relative path in the section resolves against the config's folder, as before
        assert episode_settings(new).oracle_trajectories == (tmp_path / "plans").resolve()


def test_overrides_take_the_former_spellings_and_say_each_once(tmp_path: Path) -> None:
    data = {"name": "over", "suite": str(REPO / "tasks"), "episodes": {"modes": ["composite"], "max_steps": 50}}
    new = write(tmp_path / "new.yaml", data)
    old = write(tmp_path / "old.yaml", former_layout(data))
    modes, steps = "notice: modes is now episodes.modes", "notice: max_steps is now episodes.max_steps"
    for path, expected in [(new, [steps]), (old, [modes, steps])]:  # --modes is a flag: nothing to say of it
        config, said = loaded(path, modes=["primitive"], settings=["max_steps=7"])
        assert (episode_settings(config).modes, episode_settings(config).max_steps) == (["primitive"], 7)
        assert said == expected  # the old file's max_steps and --set's: said once
    config, said = loaded(new, values={"episodes.max_steps": 8})
    assert episode_settings(config).max_steps == 8 and said == []


def test_python_keywords_take_the_former_spellings(capsys: pytest.CaptureFixture[str]) -> None:
    by_key = api.sweep_config(DEMO, episodes__modes=["primitive"], episodes__max_steps=3)
    assert capsys.readouterr().err == ""
    for source in (DEMO, api.sweep_config(DEMO)):  # a file, or a config object
        assert api.sweep_config(source, modes=["primitive"], max_steps=3) == by_key
        err = capsys.readouterr().err
        assert "notice: modes is now episodes.modes" in err and "notice: max_steps is now episodes.max_steps" in err


def test_a_key_given_both_at_the_top_level_and_in_episodes_is_one_line_error(tmp_path: Path) -> None:
    data = {"name": "twice", "suite": str(REPO / "tasks"), "max_steps": 5, "episodes": {"max_steps": 7}}
    path = write(tmp_path / "twice.yaml", data)
    done = invoke("plan", str(path))
    expected = f"error: {path}: max_steps is given both at the top level and as episodes.max_steps: keep "
    assert done.returncode == 2 and done.stderr.startswith(expected), done.stderr
    assert len(done.stderr.strip().splitlines()) == 1
    with pytest.raises(ValidationError, match=r"max_steps is given both at the top level and as episodes\.max_steps"):
        SweepConfig.model_validate(data)  # a config built in Python, or a stored one, says the same
    with pytest.raises(ConfigError, match=r"episodes\.max_steps: .* must be a positive integer, not 'many'"):
        loaded(write(tmp_path / "bad.yaml", {**data, "max_steps": "many", "episodes": {}}))  # moved, then checked


def test_the_notices_reach_standard_error_one_line_per_key(tmp_path: Path) -> None:
    data = {"name": "said", "suite": str(REPO / "tasks"), "tasks": {"limit": 1}, "modes": ["composite"], "seeds": 1}
    done = invoke("plan", str(write(tmp_path / "said.yaml", {**data, "max_steps": 9})), "--set", "max_steps=10")
    assert done.returncode == 0, done.stderr
    notices = [line for line in done.stderr.splitlines() if line.startswith("notice: ")]
    assert notices == ["notice: modes is now episodes.modes", "notice: max_steps is now episodes.max_steps"]


SINGLE_ANSWERS = [
    ("drag", "drag-tasks", "memory and synthetic are for task suites, not the single-step drag benchmark"),
    ("perception", "perception-items", "memory and synthetic are for task suites, not the perception benchmark"),
    ("audit", "tasks", "the grader audit calls no model: leave models, memory and synthetic out"),
]


@pytest.mark.parametrize(("benchmark", "suite", "message"), SINGLE_ANSWERS)
@pytest.mark.parametrize("key", ["memory", "synthetic"])
def test_other_benchmarks_refuse_memory_and_synthetic_in_either_layout(
    tmp_path: Path, benchmark: str, suite: str, message: str, key: str
) -> None:
    value = {"kind": "online"} if key == "memory" else {}
    base = {"name": "other", "benchmark": benchmark, "suite": str(REPO / suite)}
    for data in ({**base, key: value}, {**base, EPISODES_KEY: {key: value}}):
        with pytest.raises(ConfigError, match=message):
            loaded(write(tmp_path / "other.yaml", data))


@pytest.mark.parametrize(("benchmark", "suite"), [(b, s) for b, s, _ in SINGLE_ANSWERS])
def test_other_benchmarks_read_the_episode_keys_as_another_kinds_section(
    tmp_path: Path, benchmark: str, suite: str
) -> None:
    """As before, they accept the episode settings and plan no differently; and now, like any other kind's section,
    those are no part of their sweep's identity."""
    base = {"name": "other", "benchmark": benchmark, "suite": str(REPO / suite), "tasks": {"limit": 2}}
    plain, said = loaded(write(tmp_path / "plain.yaml", base))
    given, given_said = loaded(write(tmp_path / "given.yaml", {**base, "modes": ["primitive"], "max_steps": 3}))
    assert said == [] and given_said == [
        "notice: modes is now episodes.modes",
        "notice: max_steps is now episodes.max_steps",
    ]
    assert episode_settings(given).max_steps == 3 and job_ids(given) == job_ids(plain)
    assert config_hash(given) == config_hash(plain)
    assert config_hash(given) != config_hash(given.model_copy(update={"seeds": [0, 1]}))  # its own fields count


@pytest.mark.parametrize("folder", ["episodes", "drag", "perception"])
def test_a_manifest_of_the_former_layout_validates_silently_and_hashes_as_its_config(
    folder: str, capsys: pytest.CaptureFixture[str]
) -> None:
    manifest = read_manifest(OLD_RUNS / folder)
    assert manifest is not None and "max_steps" in manifest.config and EPISODES_KEY not in manifest.config
    stored = SweepConfig.model_validate(manifest.config)
    assert "notice" not in capsys.readouterr().err  # a stored config is read, not told off
    assert stored.model_dump(mode="json")[EPISODES_KEY]["max_steps"] == manifest.config["max_steps"]
    config, said = loaded(OLD_RUNS / "configs" / f"{folder}.yaml")  # the very file that made the run
    assert _hash_as_now(manifest) == config_hash(config) == config_hash(stored)
    moved = ["notice: modes is now episodes.modes", "notice: max_steps is now episodes.max_steps"]
    assert said == (moved if folder == "episodes" else [])


def test_a_manifest_reads_alike_in_either_layout(tmp_path: Path) -> None:
    """What reports and the viewer read of a run's config (its modes, its episode clock), from a manifest written
    before ``episodes:`` existed and from one written now."""
    manifest = read_manifest(OLD_RUNS / "episodes")
    assert manifest is not None
    rewritten = manifest.model_copy(
        update={"config": SweepConfig.model_validate(manifest.config).model_dump(mode="json")}
    )
    assert "modes" not in rewritten.config and rewritten.config[EPISODES_KEY]["modes"] == ["composite", "primitive"]
    assert jobs_per_group(manifest) == jobs_per_group(rewritten) == 2  # 2 tasks x 1 seed per mode

    clock = {"mode": "virtual", "start_ms": 1000, "settle_ms": 500, "think_ms": 0}
    pages = []
    for name, config in [("old", {"episode_clock": clock}), ("new", {EPISODES_KEY: {"episode_clock": clock}})]:
        run = make_run(tmp_path / name, [job("j1")], planned=1, tasks=1, config={"agent": "oracle", **config})
        page = ViewerSite([run]).get("runs/0/index.html")
        assert page is not None and page.body is not None
        pages.append(page.body.decode())
    shown = f"<th>episode clock</th><td>{json.dumps(clock)}</td>".replace('"', "&#34;")
    assert all(shown in page for page in pages), pages[0]


def test_an_old_run_views_and_exports(tmp_path: Path) -> None:
    run_dir = tmp_path / "episodes"
    shutil.copytree(OLD_RUNS / "episodes", run_dir)
    viewed = invoke("view", str(run_dir), "--export", str(tmp_path / "site"))
    assert viewed.returncode == 0, viewed.stderr
    assert (tmp_path / "site" / "runs" / "0" / "index.html").is_file()
    for fmt in ("leaderboard", "atif"):
        exported = invoke("export", str(run_dir), "--format", fmt, "--out", str(tmp_path / fmt))
        assert exported.returncode == 0, exported.stderr
        assert any((tmp_path / fmt).iterdir())


def test_an_old_run_is_refused_for_its_harness_only_whichever_layout_the_config_uses(tmp_path: Path) -> None:
    """The kept run was planned by older code (another harness), so resuming it needs --force; the refusal must
    name that alone, never "another sweep config", whether the config writes the episode keys the old way (the very
    file that made it) or under ``episodes:``; a config that does change the sweep is named as such."""
    run_dir = tmp_path / "episodes"
    shutil.copytree(OLD_RUNS / "episodes", run_dir)
    old_file = OLD_RUNS / "configs" / "episodes.yaml"
    data = yaml.safe_load(old_file.read_text())
    new = {**{k: v for k, v in data.items() if k not in moved_keys()}, "suite": str(REPO / "tasks")}
    new[EPISODES_KEY] = {key: data[key] for key in moved_keys() if key in data}
    new_file = write(tmp_path / "configs" / "episodes.yaml", new)
    changed_file = write(tmp_path / "configs" / "changed.yaml", {**new, "seeds": 2})
    for config in (old_file, new_file):
        done = invoke("run", str(config), "--out", str(run_dir))
        out = done.stdout + done.stderr
        assert done.returncode == 2 and "harness fingerprint 433e91e37d952023 ->" in out, out
        assert "sweep config" not in out, out
    done = invoke("run", str(changed_file), "--out", str(run_dir))
    assert done.returncode == 2 and "sweep config" in done.stdout + done.stderr


@pytest.mark.ray
def test_a_run_made_with_former_keys_resumes_from_episodes_and_back(tmp_path: Path, shared_ray: int) -> None:
    data = {
        "name": "layouts",
        "suite": str(REPO / "tasks"),
        "tasks": {"ids": TASKS},
        "agent": "oracle",
        "seeds": 2,
        "episodes": {"modes": ["composite"], "max_steps": 5, "synthetic": {"duration_s": 0}},
        "output": str(tmp_path / "run"),
    }
    old = write(tmp_path / "old.yaml", former_layout(data))
    new = write(tmp_path / "new.yaml", data)
    code, out = run_here(old)
    assert code == 0 and "4 job(s) planned" in out and "0 already decided, 4 to run" in out, out
    for config in (new, old):
        code, out = run_here(config)
        assert code == 0 and "4 already decided, 0 to run" in out, out
    manifest = read_manifest(tmp_path / "run")
    assert (
        manifest is not None and manifest.config[EPISODES_KEY]["max_steps"] == 5 and "max_steps" not in manifest.config
    )
