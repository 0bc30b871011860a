"""A fourth job kind from a plugin package, driver and worker side, run end to end: planned from its own suite,
run by its own runner on the sweep's Ray workers, recorded with its name in the benchmark column and in a result
table of its own, configured by a section of its own, reported by its own report, shown by the viewer, resumed,
and given its cells, axis and section in the diagnosis over several kinds. What it takes is what this module's
plugin holds: a ``Kind`` (with its config section, row model, viewer panel and diagnosis part), a ``JobBody``, a
worker spec, a ``WorkerKind`` and two entry points."""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path

import pytest
import yaml

from scratchworld_dist import api
from scratchworld_dist._errors import ConfigError
from scratchworld_dist._run import config_hash
from scratchworld_dist.kinds import job_kind, kind_names
from scratchworld_dist.kinds._registry import _registered
from scratchworld_dist.reports import diagnosis_models, report_runs, report_schemas
from scratchworld_dist.results import RunStore, kind_of_run
from scratchworld_dist.results._schema import row_tables
from scratchworld_dist.sweep import SweepConfig, load_sweep_config
from scratchworld_dist.viewer import ViewerSite
from tests.conftest import REPO
from tests.support.cli_runner import invoke
from tests.support.run_dirs import job, make_run
from tests.support.sweep_driver import run_here

PLUGIN = '''
"""Echo: each item names a word; a job passes when the word is "yes"."""
import hashlib
from html import escape
from pathlib import Path

from pydantic import BaseModel, ConfigDict

from scratchworld_dist.kinds.base import Kind
from scratchworld_dist.reports import Rate, rate_cell
from scratchworld_dist.results import RunStore, effective_rows
from scratchworld_dist.sweep import JobBody, JobSpec, RunPlan, SuiteInfo, identity_id, suite_hash
from scratchworld_dist.viewer import AttemptPanel
from workers.contract import AgentUnavailableError, JobResult, ModelSpec


class EchoSection(BaseModel):
    """The ``echo:`` section of a sweep config."""
    model_config = ConfigDict(extra="forbid")
    passing_word: str = "yes"


class EchoRow(BaseModel):
    """A row of the ``echoes`` table."""
    job_id: str
    attempt: int
    word: str
    passing_word: str


class EchoReport(BaseModel):
    echoed_yes: int
    jobs: int


class EchoCells(BaseModel):
    """The echo cells of a diagnosis row."""
    echo_yes: Rate | None = None


class EchoAxes(BaseModel):
    echo_words: list[str] = []


class EchoInDiagnosis(BaseModel):
    echo: EchoReport | None = None


class EchoDiagnosis:
    cells_model = EchoCells
    axes_model = EchoAxes
    section_model = EchoInDiagnosis
    runs_label = "Echo runs"
    definitions = "Echo yes = passed / decided echo jobs."

    def units(self, group):
        rows = [row for run in group.runs for row in run.rows]
        return [(row.job_id, row) for row in effective_rows(rows)]

    def cells(self, units):
        decided = [row for row in units if row.outcome != "error"]
        passed = sum(row.outcome == "passed" for row in decided)
        return EchoCells(echo_yes=Rate(value=passed / len(decided), n=len(decided)) if decided else None)

    def axes(self, units):
        return EchoAxes(echo_words=sorted({row.task_id for row in units}))

    def header(self, table):
        return [f"echo yes ({', '.join(table.echo_words)})"]

    def row(self, row, table):
        return [rate_cell(row.echo_yes)]

    def section(self, group):
        rows = [row for run in group.runs for row in run.rows]
        return EchoReport(echoed_yes=sum(row.outcome == "passed" for row in rows), jobs=len(rows))

    def render_section(self, section, fmt, group):
        text = f"# Echo report\\n\\n{section.echoed_yes} of {section.jobs} echoed yes\\n"
        return text if fmt == "md" else f"<p>{escape(text)}</p>"


DIAGNOSIS = EchoDiagnosis()


class EchoBody(JobBody):
    kind: str = "echo"
    word: str
    passing_word: str

    def columns(self):
        return {"mode": "primitive", "max_steps": 1}


class EchoItem(BaseModel):
    id: str


class EchoPayload(BaseModel):
    task_id: str
    word: str
    passing_word: str = "yes"


class EchoContent(BaseModel):
    task: EchoItem
    payload: EchoPayload
    task_hash: str


class EchoSpec(BaseModel):
    job_id: str
    attempt: int
    task_id: str
    timeout_s: float
    harness: str | None = None
    agent: object = None
    agent_code: str | None = None
    model: ModelSpec | None = None
    seed: int = 0
    llm: object = None
    model_cache: object = None


class EchoKind(Kind):
    name = "echo"
    title = "echo"
    needs_browser = False
    tables = {"echoes": EchoRow}
    config_section = EchoSection
    regrade_refusal = "an echo run stores words, not projects"

    def check_agent(self, agent):
        if agent.name != "echo" or agent.params:
            raise AgentUnavailableError(f"the echo benchmark's agent is echo, not {agent.name!r}")


    def needs_model(self, config):
        return False


    def plan(self, config, harness, notice):
        passing = config.section(self.name, EchoSection).passing_word
        lines = (config.suite / "items.txt").read_text().split("\\n")
        contents = []
        for line in filter(None, lines):
            item_id, word = line.split()
            digest = hashlib.sha256(line.encode()).hexdigest()[:16]
            payload = EchoPayload(task_id=item_id, word=word, passing_word=passing)
            contents.append(EchoContent(task=EchoItem(id=item_id), payload=payload, task_hash=digest))
        jobs = [
            JobSpec(
                job_id=identity_id({"echo": c.task.id, "hash": c.task_hash, "seed": seed, "harness": harness.digest}),
                model=None, agent=config.agent, task_id=c.task.id, category="echo", task_hash=c.task_hash, seed=seed,
                harness=harness.digest, body=EchoBody(word=c.payload.word, passing_word=passing),
            )
            for seed in config.seeds for c in contents
        ]
        root, count = str(config.suite), len(contents)
        info = SuiteInfo(name="echo", kind="echo", root=root, hash=suite_hash(contents), tasks=count)
        return RunPlan(config=config, harness=harness, suite=info, contents=contents, jobs=jobs)

    def worker_job(self, job, attempt, timeout_s):
        return EchoSpec(**job.worker_header(attempt, timeout_s))

    def own_rows(self, job, result, artifact_dir):
        row = EchoRow(job_id=job.job_id, attempt=result.attempt, word=job.body.word, passing_word=job.body.passing_word)
        return {"echoes": [row]}

    def attempt_panel(self, rows, root, run_dir):
        (row,) = rows["echoes"]
        return AttemptPanel(title="Echoed", html=f"<p class=echoed>{escape(row.word)}</p>", shows_project=False)



    def report(self, run_dirs, fmt, *, force):
        rows = [row for run_dir in run_dirs for row in RunStore(Path(run_dir)).job_rows()]
        passed = sum(row.outcome == "passed" for row in rows)
        return f"# Echo report\\n\\n{passed} of {len(rows)} echoed yes\\n", []

    def report_model(self):
        return EchoReport

    def report_data(self, run_dirs, *, force):
        rows = [row for run_dir in run_dirs for row in RunStore(Path(run_dir)).job_rows()]
        return EchoReport(echoed_yes=sum(row.outcome == "passed" for row in rows), jobs=len(rows))

    def report_html(self, run_dir):
        text, warnings = self.report([run_dir], "md", force=False)
        return f"<p>{text}</p>", warnings

    def diagnosis(self):
        return DIAGNOSIS



class EchoWorkerKind:
    name = "echo"
    specs = (EchoSpec,)
    payloads = (EchoPayload,)
    code = ()
    needs_browser = False

    async def run(self, host, spec, payload):
        outcome = "passed" if payload.word == payload.passing_word else "failed"
        return JobResult(job_id=spec.job_id, attempt=spec.attempt, outcome=outcome, stop_reason="done")


KIND = EchoKind()
WORKER_KIND = EchoWorkerKind()
'''


@pytest.fixture(scope="module")
def echo_plugin(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Path]:
    """The plugin installed (its module and dist-info on the path of this process and of its Ray's workers)."""
    site = tmp_path_factory.mktemp("echo-plugin")
    (site / "echo_kind.py").write_text(PLUGIN)
    info = site / "echo_kind-1.0.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: echo-kind\nVersion: 1.0\n")
    entry_points = (
        "[scratchworld.kinds]\necho = echo_kind:KIND\n\n[scratchworld.worker_kinds]\necho = echo_kind:WORKER_KIND\n"
    )
    (info / "entry_points.txt").write_text(entry_points)
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
    with pytest.raises(ConfigError, match=r"echo\.passing_words: Extra inputs are not permitted"):
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
