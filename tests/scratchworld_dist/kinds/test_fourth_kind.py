"""A kind added as docs/architecture.md ("Add a kind") says: the test builds the package from the doc's own
blocks, checks it is one folder per side plus its metadata, installs it with pip, and runs it end to end:
planned from its own suite, run by its own worker kind on the sweep's Ray workers with an agent from the group
it declares, recorded with its name in the benchmark column and in a table of its own, configured by a section
of its own, reported by its own report, shown by the viewer, resumed, and given its cells, axis and section in
the diagnosis over several kinds. It edits no file of this repository."""

from __future__ import annotations

import json
import re
from collections.abc import Iterator
from pathlib import Path

import pytest
import yaml

from scratchworld_dist import api
from scratchworld_dist._errors import ConfigError
from scratchworld_dist._sweep_manifest import config_hash
from scratchworld_dist.kinds import job_kind, kind_names
from scratchworld_dist.kinds._registry import _registered
from scratchworld_dist.reports import diagnosis_models, report_runs, report_schemas
from scratchworld_dist.results import RunStore, kind_of_run
from scratchworld_dist.results._schema import row_tables
from scratchworld_dist.sweep import SweepConfig, load_sweep_config
from scratchworld_dist.viewer import ViewerSite
from tests.conftest import REPO
from tests.support.cli_runner import invoke
from tests.support.plugins import install_package
from tests.support.run_dirs import job, make_run
from tests.support.sweep_driver import run_here
from workers.agent_api import agent_class, registered_agents
from workers.contract import AgentUnavailableError

DOC = REPO / "docs" / "architecture.md"
FILE_BLOCK = re.compile(r"^File `([^`]+)`:\n\n```\w+\n(.*?)^```$", re.M | re.S)


def doc_package() -> dict[str, str]:
    """The files the doc's "Add a kind" section gives, by path, as it gives them."""
    text = DOC.read_text()
    section = text[text.index("## Add a kind") :]
    section = section[: section.index("\n## ")] if "\n## " in section else section
    return {path: body for path, body in FILE_BLOCK.findall(section)}


def test_the_doc_s_kind_is_one_folder_per_side_and_its_metadata() -> None:
    files = doc_package()
    assert set(files) == {
        "pyproject.toml",
        "echo_bench/__init__.py",
        "echo_bench/driver/__init__.py",
        "echo_bench/worker/__init__.py",
    }
    assert "from workers" not in files["echo_bench/__init__.py"]
    assert "scratchworld_dist" not in files["echo_bench/worker/__init__.py"]  # a worker needs no driver code


@pytest.fixture(scope="module")
def echo_plugin(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Path]:
    """The doc's package installed with pip into a folder of its own, on the path of this process and of its
    Ray's workers."""
    site = install_package(tmp_path_factory.mktemp("echo-plugin"), doc_package())
    with pytest.MonkeyPatch.context() as patch:
        patch.syspath_prepend(str(site))
        patch.setenv("PYTHONPATH", f"{site}:{REPO}")
        _registered.cache_clear()
        row_tables.cache_clear()
        yield site
    _registered.cache_clear()
    row_tables.cache_clear()


@pytest.fixture(scope="module")
def echo_ray(echo_plugin: Path) -> Iterator[int]:
    """The module's Ray, started once the plugin is on the path its workers inherit."""
    from scratchworld_dist.scheduling import ray_runtime

    with ray_runtime(None, None) as slots:
        yield slots


@pytest.mark.ray
def test_a_plugin_kind_is_planned_run_recorded_reported_and_resumed(tmp_path: Path, echo_ray: int) -> None:
    assert kind_names() == ["tasks", "drag", "perception", "audit", "echo"]  # built-in ones first
    suite = tmp_path / "echo-suite"
    suite.mkdir()
    (suite / "items.txt").write_text("a yes\nb no\nc yes\n")
    config = tmp_path / "echo.yaml"
    sweep = {"name": "echo", "benchmark": "echo", "suite": str(suite), "agent": "echo", "seeds": 2, "echo": {}}
    config.write_text(yaml.safe_dump({**sweep, "output": str(tmp_path / "run")}))
    code, out = run_here(config)
    assert code == 0, out
    rows = RunStore(tmp_path / "run").job_rows()
    assert len(rows) == 6 and {row.benchmark for row in rows} == {"echo"}
    assert sorted(row.outcome for row in rows) == ["failed"] * 2 + ["passed"] * 4
    assert {row.mode for row in rows} == {"primitive"} and kind_of_run(tmp_path / "run") is job_kind("echo")
    echoes = RunStore(tmp_path / "run").read_table("echoes").to_pylist()
    assert sorted(row["word"] for row in echoes) == ["no", "no", "yes", "yes", "yes", "yes"]
    assert {row["passing_word"] for row in echoes} == {"yes"} and not (tmp_path / "run" / "drags").exists()
    failed = next(row.job_id for row in rows if row.outcome == "failed")
    page = ViewerSite([tmp_path / "run"]).get(f"runs/0/jobs/{failed}.html")
    assert page is not None and page.body is not None
    assert b"<h3>Echoed</h3>" in page.body and b"<p class=echoed>no</p>" in page.body
    assert b"Final project" not in page.body
    assert api.report([tmp_path / "run"]).model_dump() == {"echoed_yes": 4, "jobs": 6}
    assert "echo-report.schema.json" in report_schemas()
    report = invoke("report", str(tmp_path / "run"))
    assert report.returncode == 0 and report.stdout.startswith("# Echo report") and "4 of 6 echoed yes" in report.stdout
    code, out = run_here(config)
    assert code == 0 and "6 already decided, 0 to run" in " ".join(out.split()), out
    regrade = invoke("regrade", str(tmp_path / "run"), "--out", str(tmp_path / "regraded"))
    assert regrade.returncode != 0 and "an echo run stores words, not projects" in regrade.stderr
    config.write_text(yaml.safe_dump({**sweep, "echo": {"passing_word": "no"}, "output": str(tmp_path / "run")}))
    code, out = run_here(config)  # the plugin's own section shapes its jobs: another sweep
    assert code != 0 and "holds results of another sweep (sweep config" in " ".join(out.split()), out


def test_a_plugin_kind_brings_agents_in_a_group_it_declares(echo_plugin: Path, tmp_path: Path) -> None:
    """Its worker kind names the group (``agents``); the agent registry finds the kind's agents there, and only
    there, with no table of this package edited."""
    assert registered_agents("echo") == ["echo"] and "echo" not in registered_agents("tasks")
    assert agent_class("echo", "echo").__module__ == "echo_bench.worker"
    with pytest.raises(AgentUnavailableError, match=r"^agent echo_bench.worker:EchoAgent serves echo, not tasks$"):
        agent_class("echo_bench.worker:EchoAgent")
    with pytest.raises(AgentUnavailableError, match=r"^agent pathlib:Path serves tasks, not echo$"):
        agent_class("pathlib:Path", "echo")
    config = tmp_path / "echo.yaml"
    config.write_text(yaml.safe_dump({"name": "e", "benchmark": "echo", "suite": str(tmp_path), "agent": "oracle"}))
    with pytest.raises(ConfigError) as caught:
        load_sweep_config(config)
    message = str(caught.value)
    assert "agent 'oracle' is not registered for the echo benchmark (registered: echo)" in message, message
    assert "\n" not in message


def test_a_plugin_kind_adds_its_cells_axis_and_section_to_the_diagnosis(echo_plugin: Path, tmp_path: Path) -> None:
    echoes = [
        job(f"e-{word}", outcome, benchmark="echo", agent="echo", model="-", task_id=word, mode="primitive")
        for word, outcome in (("yes", "passed"), ("no", "failed"), ("maybe", "error"))
    ]
    echo_run = make_run(tmp_path / "echo", echoes, planned=3, tasks=3, config={"benchmark": "echo"}, name="echo")
    episode = [job("t1", benchmark="tasks", agent="echo", model="-")]  # the same scripted agent, in an episode
    episodes = make_run(tmp_path / "episodes", episode, planned=1, tasks=1, name="episodes")
    text, _ = report_runs([echo_run, episodes], "json")
    data = json.loads(text)
    # The plugin's section, axis and cells come after the built-in kinds', where its rank puts them.
    assert list(data) == ["version", "diagnosis", "episodes", "drag", "perception", "echo"]
    assert data["echo"] == {"echoed_yes": 1, "jobs": 3}
    table = data["diagnosis"]
    assert list(table) == ["version", "runs", "drag_settings", "perception_kinds", "echo_words", "warnings", "rows"]
    assert table["echo_words"] == ["maybe", "no", "yes"]
    (row,) = table["rows"]
    assert list(row)[-2:] == ["perception", "echo_yes"] and row["label"] == "echo [scripted]"
    assert row["echo_yes"] == {"value": 0.5, "n": 2} and row["composite_sr"] == {"value": 1.0, "n": 1}
    report = diagnosis_models().report.model_validate_json(text)
    assert report.echo.echoed_yes == 1 and report.diagnosis.rows[0].echo_yes.n == 2  # typed, not extra fields
    markdown, _ = report_runs([echo_run, episodes], "md")
    assert "| echo yes (maybe, no, yes) |" in markdown and "| 50.0% (n=2) |" in markdown
    assert "Echo runs: echo (" in markdown and "Echo yes = passed / decided echo jobs." in markdown
    assert markdown.rstrip().endswith("1 of 3 echoed yes")
    schema = report_schemas()["diagnosis-report.schema.json"]
    assert schema["properties"]["echo"]["anyOf"][0] == {"$ref": "#/$defs/EchoReport"}
    assert "echo_yes" in schema["$defs"]["DiagnosisRow"]["properties"]
    assert "echo_words" in schema["$defs"]["DiagnosisTable"]["properties"]


def test_a_plugin_section_is_checked_and_written_back_under_its_name(echo_plugin: Path, tmp_path: Path) -> None:
    base = {"name": "e", "benchmark": "echo", "suite": str(tmp_path), "agent": "echo"}
    config = tmp_path / "echo.yaml"
    config.write_text(yaml.safe_dump({**base, "echo": {"passing_word": ["not", "a", "word"]}}))
    with pytest.raises(ConfigError, match=r"echo\.passing_word: Input should be a valid string"):
        load_sweep_config(config)
    config.write_text(yaml.safe_dump({**base, "echo": {"passing_words": "no"}}))
    with pytest.raises(ConfigError, match=r"echo\.passing_words: unknown key"):
        load_sweep_config(config)
    config.write_text(yaml.safe_dump({**base, "echo": {"passing_word": "no"}}))
    loaded = load_sweep_config(config)
    dumped = loaded.model_dump(mode="json")
    assert dumped["echo"] == {"passing_word": "no"} and "sections" not in dumped
    assert dumped["drag"]["settings"] == ["baseline"]  # every installed kind's section, as before plugins
    assert SweepConfig.model_validate(dumped) == loaded


def test_other_kinds_sections_leave_a_sweep_s_identity_alone(echo_plugin: Path, tmp_path: Path) -> None:
    tasks = {"name": "t", "suite": str(REPO / "tasks")}
    plain = SweepConfig.model_validate(tasks)
    echoing = SweepConfig.model_validate({**tasks, "echo": {"passing_word": "no"}, "drag": {"types": ["T1"]}})
    assert config_hash(plain) == config_hash(echoing)
    drag = SweepConfig.model_validate({**tasks, "benchmark": "drag"})
    typed = drag.model_copy(update={"sections": {**drag.sections, "drag": echoing.sections["drag"]}})
    assert config_hash(drag) != config_hash(typed)  # its own section does count


def test_a_config_naming_no_installed_kind_is_one_line(tmp_path: Path) -> None:
    config = tmp_path / "bad.yaml"
    config.write_text(yaml.safe_dump({"name": "x", "benchmark": "nonesuch", "suite": str(tmp_path)}))
    done = invoke("run", str(config))
    assert done.returncode != 0
    assert "benchmark: Value error, no benchmark 'nonesuch' is installed (installed: tasks, drag, perception" in (
        done.stderr + done.stdout
    )
