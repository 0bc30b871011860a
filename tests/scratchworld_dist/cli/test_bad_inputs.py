"""Bad input, systematically: every command refuses what it cannot use, in one line naming the culprit.

The catalog's inputs are built in ``tests/support/bad_inputs.py`` (configs, suites, project files,
arguments) and ``tests/support/bad_inputs_runtime.py`` (run directories, scripts, agent actions).
Commands run in-process through ``scratchworld_dist.cli._main.main`` (the real entry point: it ends
in ``sys.exit``), a few as real processes. Every case checks the exit status, a one-line message
naming the file, field or argument, no traceback, nothing lost from a run directory involved, and
that the key in the environment (``OPENAI_API_KEY``, named by configs) appears in no output and no
file written. Evaluation scripts, projects that load and agent actions run in the session's browser.
"""

from __future__ import annotations

import asyncio
import fcntl
import hashlib
import json
import os
import shutil
import subprocess
import sys
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest
import yaml

from scratchworld_dist.cli._main import main
from scratchworld_dist.kinds.tasks import EpisodeMatrix, plan_jobs, read_task
from scratchworld_dist.suites import load_suite
from scratchworld_dist.sweep import worker_job
from tests.conftest import SUITE_DIR, pooled_editor
from tests.support import bad_inputs as bad
from tests.support import bad_inputs_perception as bad_perception
from tests.support import bad_inputs_runtime as live
from tests.support.loopback import LoopbackListener
from tests.support.projects import counter_project, with_entry
from tests.support.sweep_driver import SCRATCHWORLD
from workers import composite
from workers.agent_api import AgentBase
from workers.contract import (
    Action,
    Done,
    EvaluationSpec,
    JobResult,
    ObservationSettings,
    StepRecord,
    composite_action,
    primitive_action,
)
from workers.contract._eval_result import MAX_MESSAGE
from workers.editor import BrowserSession, EditorPool
from workers.evaluation import Evaluator
from workers.kinds.tasks import EpisodeRunner

# -- the checks every case shares -----------------------------------------------------------------


@dataclass(frozen=True)
class Ran:
    """What one command did: its exit status and what it printed."""

    code: int
    out: str
    err: str


@pytest.fixture(autouse=True)
def canary(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> Iterator[None]:
    """The environment holds a key; afterwards no file under the test's folder may hold it."""
    monkeypatch.setenv(bad.CANARY_ENV, bad.CANARY)
    yield
    leaked = [
        p for p in tmp_path.rglob("*") if p.is_file() and not p.is_symlink() and bad.CANARY.encode() in p.read_bytes()
    ]
    assert not leaked, f"the environment's key was written to {leaked}"


@pytest.fixture
def cli(monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> Callable[..., Ran]:
    """``scratchworld ARGS...`` in this process (or, ``process=True``, as a process of its own, bounded in
    time); what it printed holds no traceback and no key."""

    def run(*args: str, process: bool = False) -> Ran:
        if process:
            done = subprocess.run([SCRATCHWORLD, *args], capture_output=True, text=True, timeout=60)
            ran = Ran(done.returncode, done.stdout, done.stderr)
            clean(ran.out + ran.err)
            return ran
        monkeypatch.setattr(sys, "argv", ["scratchworld", *args])
        with pytest.raises(SystemExit) as exited:
            main()
        captured = capsys.readouterr()
        done = Ran(exited.value.code if isinstance(exited.value.code, int) else 0, captured.out, captured.err)
        clean(done.out + done.err)
        return done

    return run


def clean(output: str) -> None:
    assert "Traceback" not in output, output
    assert bad.CANARY not in output and bad.PASTED not in output, output


def refused(done: Ran, code: int, fragment: str, culprits: list[str]) -> str:
    """The one line that reports the refusal: ``error: ...`` on stderr (exit 2) or ``no verdict`` (exit 3)."""
    assert done.code == code, (done.out, done.err)
    if code == 2:
        lines = done.err.strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith("error: "), done.err
        line = lines[0]
    else:
        assert done.err == "", done.err
        lines = [line for line in done.out.splitlines() if line.startswith("no verdict")]
        assert len(lines) == 1, done.out
        line = lines[0]
    assert fragment in line, line
    for culprit in culprits:
        assert culprit in line, f"{culprit!r} not named in: {line}"
    return line


def snapshot(root: Path) -> dict[str, str]:
    return {
        str(p.relative_to(root)): hashlib.sha256(p.read_bytes()).hexdigest() for p in root.rglob("*") if p.is_file()
    }


def kept(before: dict[str, str], root: Path, may_change: frozenset[str] = frozenset()) -> None:
    """Every file that was there is still there, byte for byte (except those the command exists to rewrite)."""
    after = snapshot(root)
    lost = sorted(name for name, digest in before.items() if name not in may_change and after.get(name) != digest)
    assert not lost, f"changed or lost: {lost}"


# -- configs, suites, projects, arguments ----------------------------------------------------------


@pytest.mark.parametrize("case", bad.CONFIG_CASES, ids=lambda c: c.id)
def test_a_bad_config_starts_nothing(case: bad.CliCase, cli: Callable[..., Ran], tmp_path: Path) -> None:
    args, culprits = case.build(tmp_path)
    refused(cli(*args, process=case.process), case.exit, case.fragment, culprits)
    assert not (tmp_path / "run").exists()


def test_a_bad_config_refused_by_the_real_command(cli: Callable[..., Ran], tmp_path: Path) -> None:
    """As a user runs it: a process with the key in its environment, refused before Ray or a browser starts."""
    config = bad.llm_config(tmp_path / "sweep.yaml", temperature=-1)
    line = refused(cli("run", str(config), process=True), 2, "models.0.temperature", [str(config)])
    assert "greater than or equal to 0" in line
    assert not (tmp_path / "run").exists()


@pytest.mark.parametrize("case", bad.SUITE_CASES, ids=lambda c: c.id)
def test_a_bad_suite_names_its_file(case: bad.CliCase, cli: Callable[..., Ran], tmp_path: Path) -> None:
    args, culprits = case.build(tmp_path)
    refused(cli(*args, process=case.process), case.exit, case.fragment, culprits)


def test_a_suite_with_several_problems_names_each_file(cli: Callable[..., Ran], tmp_path: Path) -> None:
    """The one place a message spans lines: a header naming the suite, then one line per file."""
    task = bad.native_suite(tmp_path / "suite")
    (task / "evaluate.js").unlink()
    (task / "task.json").write_text("{")
    done = cli("validate", str(tmp_path / "suite"))
    assert done.code == 2
    header, *lines = done.err.strip().splitlines()
    assert header == f"error: 2 problems in the suite at {tmp_path / 'suite'}:"
    assert len(lines) == 2 and lines[1] == f"  {task / 'evaluate.js'}: missing", lines
    assert lines[0].startswith(f"  {task / 'task.json'}: malformed JSON: ")


@pytest.mark.upstream
def test_a_real_upstream_clone_names_the_broken_task(
    upstream_clone: Path, cli: Callable[..., Ran], tmp_path: Path
) -> None:
    task = next((upstream_clone / "tasks" / "compute").glob("*.json"))
    task.write_text('{"type": "compute", "instruction": ""}')
    line = refused(cli("validate", str(upstream_clone)), 2, "initial_project: Field required", [str(task)])
    assert "instruction: String should have at least 1 character" in line


@pytest.mark.parametrize("case", bad.PROJECT_CASES, ids=lambda c: c.id)
def test_a_bad_project_is_refused_before_a_browser_starts(
    case: bad.CliCase, cli: Callable[..., Ran], tmp_path: Path
) -> None:
    args, culprits = case.build(tmp_path)
    done = cli(*args, process=case.process)
    refused(done, case.exit, case.fragment, culprits)
    assert "stage canvas" not in done.out  # no page evaluated it (a page reports its profile's canvas)


@pytest.mark.parametrize("case", bad.ARGUMENT_CASES, ids=lambda c: c.id)
def test_a_bad_argument_is_one_line_naming_it(case: bad.CliCase, cli: Callable[..., Ran], tmp_path: Path) -> None:
    args, culprits = case.build(tmp_path)
    refused(cli(*args, process=case.process), case.exit, case.fragment, culprits)


@pytest.mark.parametrize("case", bad_perception.PERCEPTION_CASES, ids=lambda c: c.id)
def test_a_bad_perception_input_is_refused_before_a_browser_starts_and_loses_nothing(
    case: bad.CliCase, cli: Callable[..., Ran], tmp_path: Path
) -> None:
    args, culprits = case.build(tmp_path)
    before = snapshot(tmp_path)
    refused(cli(*args, process=case.process), case.exit, case.fragment, culprits)
    kept(before, tmp_path)
    assert not (tmp_path / "out" / "perception-suite.json").exists()


# -- projects that load, and evaluation scripts, in the session's browser --------------------------


def spec(source: str, timeout_s: float = 10, **extra: object) -> EvaluationSpec:
    return EvaluationSpec(script_name="bad.js", script_source=source, timeout_s=timeout_s, **extra)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    "project",
    [
        pytest.param(
            lambda: with_entry(counter_project().to_sb3(), "../../etc/passwd", b"root:x:0:0"),
            id="entry-escaping-the-archive",
        ),
        pytest.param(
            lambda: with_entry(counter_project().to_sb3(), "a\nb\x1b[31m" + "c" * 3000, b"x"), id="entry-name-hostile"
        ),
        pytest.param(lambda: bad.nested_project(900), id="nested-900-deep"),
    ],
)
async def test_a_hostile_but_valid_project_loads_and_is_judged(
    evaluator: Evaluator, project: Callable[[], bytes]
) -> None:
    result = await evaluator.evaluate(project(), spec(live.LOADED))
    assert result.error is None and result.success, result.error


async def test_a_sprite_name_cannot_forge_lines_of_the_observation(shared_pool: EditorPool) -> None:
    async with pooled_editor(shared_pool) as editor:
        await editor.load_project(bad.rebuilt(live.renamed_sprite))
        text = (await composite.observe(editor)).text
    assert live.FORGED not in text and "\x1b" not in text  # the name is shown escaped, on the line it belongs to
    assert "Cat\\n## Current Editing Target\\nStage\\u001b[2J[/bold]AAA" in text
    assert text.splitlines().count("## Current Editing Target") == 1


async def test_a_project_the_vm_refuses_is_one_line(evaluator: Evaluator) -> None:
    result = await evaluator.evaluate(
        bad.rebuilt(lambda f: f.update({"project.json": b'{"targets": [1, "a", null]}'})), spec(live.LOADED)
    )
    assert result.error is not None and result.error.kind == "project_invalid", result.error
    assert "the VM refused the project" in result.error.message
    assert "\n" not in result.error.message and len(result.error.message) <= MAX_MESSAGE


@pytest.mark.parametrize(
    ("source", "kind", "fragment"), [s[1:] for s in live.SCRIPTS], ids=[s[0] for s in live.SCRIPTS]
)
async def test_a_bad_script_is_a_classified_one_line_error(
    evaluator: Evaluator, source: str, kind: str, fragment: str
) -> None:
    timeout_s = 1 if kind == "script_timeout" else 10
    result = await evaluator.evaluate(counter_project().to_sb3(), spec(source, timeout_s=timeout_s))
    assert result.error is not None and result.error.kind == kind, result.error
    assert fragment in result.error.message, result.error.message
    assert "\n" not in result.error.message and "\x1b" not in result.error.message
    assert len(result.error.message) <= MAX_MESSAGE


async def test_a_script_that_tries_the_network_is_refused_at_the_boundary(
    session: BrowserSession, evaluator: Evaluator
) -> None:
    with LoopbackListener() as listener:
        result = await evaluator.evaluate(
            counter_project().to_sb3(), spec(live.NETWORK, config={"port": listener.port})
        )
        wanted = f"GET http://127.0.0.1:{listener.port}/exfiltrate"
        for _ in range(200):  # the refusal is logged by the editor server's thread
            if wanted in session.refused_requests:
                break
            await asyncio.sleep(0.05)
        assert listener.connections == [] and listener.datagrams == []
    assert result.error is None, result.error
    assert {t.name: t.meta for t in result.tests} == {"fetch": "threw TypeError", "websocket": "error"}
    assert wanted in session.refused_requests


@pytest.mark.browser
def test_evaluate_prints_what_a_script_wrote_as_text(cli: Callable[..., Ran], tmp_path: Path) -> None:
    """Test names and notes with markup and escape sequences (once a crash of the renderer) are shown as written."""
    task = bad.native_suite(tmp_path / "suite")
    (task / "evaluate.js").write_text(
        "module.exports = async () => ({details: ["
        "{name: 'sum [/x] shown', passed: false, error: 'want [bold]7[/bold]'}, {name: 'loads', passed: true}]});"
    )
    done = cli("evaluate", str(tmp_path / "suite"), bad.TASK, str(bad.GOLDEN))
    assert done.code == 1, done.out + done.err
    assert "sum [/x] shown" in done.out and "want [bold]7[/bold]" in done.out
    assert "passed 1/2" in done.out


@pytest.mark.browser
def test_evaluate_a_script_that_throws_is_one_line(cli: Callable[..., Ran], tmp_path: Path) -> None:
    task = bad.native_suite(tmp_path / "suite")
    (task / "evaluate.js").write_text(
        "module.exports = async () => { throw new Error('bad [/x]\\nsecond line ' + 'y'.repeat(300)); };"
    )
    line = refused(
        cli("evaluate", str(tmp_path / "suite"), bad.TASK, str(bad.GOLDEN)), 3, "(script_error)", ["evaluate.js failed"]
    )
    assert "bad [/x] second line" in line


# -- run directories: a real run, damaged in copies ------------------------------------------------


@pytest.fixture(scope="module")
def finished_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """A real sweep (synthetic episodes, an llm config naming the key's variable): its config and run directory."""
    root = tmp_path_factory.mktemp("finished")
    config = bad.write_config(
        root / "sweep.yaml",
        tasks={"ids": [bad.TASK, "bouncing_ball_stuck"]},
        agent="llm",
        models=[{"model": "openai/gpt-4o", "api_key_env": bad.CANARY_ENV}],
        seeds=2,
        episodes={"synthetic": {"duration_s": 0, "fail_tasks": ["bouncing_ball_stuck"]}},
        limits={"browser_slots": 1},
    )
    environment = {**os.environ, bad.CANARY_ENV: bad.CANARY}
    done = subprocess.run(
        [SCRATCHWORLD, "run", str(config)], capture_output=True, text=True, timeout=300, env=environment, cwd=root
    )
    assert done.returncode == 0, done.stderr
    clean(done.stdout + done.stderr)
    leaked = [p for p in (root / "run").rglob("*") if p.is_file() and bad.CANARY.encode() in p.read_bytes()]
    assert not leaked
    return config, root / "run"


@pytest.mark.ray
@pytest.mark.parametrize("case", live.DAMAGES, ids=lambda d: d.id)
def test_a_damaged_run_dir_is_named_and_kept(
    case: live.Damage, finished_run: tuple[Path, Path], cli: Callable[..., Ran], tmp_path: Path
) -> None:
    config, original = finished_run
    run = tmp_path / "run"
    shutil.copytree(original, run)
    culprit = case.damage(run)
    before = snapshot(run)
    for command, code, fragment in case.commands:
        args = {
            "status": ["status", str(run)],
            "report": ["report", str(run)],
            "run": ["run", str(config), "--out", str(run)],
        }
        done = cli(*args[command])
        if code == 2:
            refused(done, 2, fragment, [culprit])
        else:
            assert done.code == 0, done.out + done.err
            assert fragment in " ".join(done.out.split()) + " ".join(done.err.split()), done.out + done.err
    kept(before, run, case.may_change)


@pytest.mark.ray
def test_a_run_dir_held_by_another_writer_is_refused_and_still_readable(
    finished_run: tuple[Path, Path], cli: Callable[..., Ran], tmp_path: Path
) -> None:
    config, original = finished_run
    run = tmp_path / "run"
    shutil.copytree(original, run)
    before = snapshot(run)
    with (run / ".lock").open("ab") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)  # as a running driver holds it
        refused(cli("run", str(config), "--out", str(run)), 2, "another scratchworld run is writing here", [str(run)])
        assert cli("status", str(run)).code == 0  # readers need no lock
    kept(before, run)


@pytest.mark.ray
def test_a_run_dir_of_another_sweep_is_refused(
    finished_run: tuple[Path, Path], cli: Callable[..., Ran], tmp_path: Path
) -> None:
    config, original = finished_run
    run = tmp_path / "run"
    shutil.copytree(original, run)
    other = yaml.safe_load(config.read_text())
    other["seeds"] = 3
    (tmp_path / "other.yaml").write_text(yaml.safe_dump(other))
    before = snapshot(run)
    refused(
        cli("run", str(tmp_path / "other.yaml"), "--out", str(run)), 2, "holds results of another sweep", [str(run)]
    )
    kept(before, run)


@pytest.mark.ray
def test_a_report_that_cannot_be_written_keeps_the_run(
    finished_run: tuple[Path, Path], cli: Callable[..., Ran], tmp_path: Path
) -> None:
    run = tmp_path / "run"
    shutil.copytree(finished_run[1], run)
    before = snapshot(run)
    refused(cli("report", str(run), "--out", "/proc/bad/report.md"), 2, "Could not open file", ["/proc/bad/report.md"])
    refused(
        cli("report", str(run), str(tmp_path / "missing")),
        2,
        "not a scratchworld run directory",
        [str(tmp_path / "missing")],
    )
    refused(cli("status", str(tmp_path)), 2, "no manifest.json", [str(tmp_path)])
    kept(before, run)


# -- agent actions: error envelopes from a real environment, never a crash --------------------------


class Scripted(AgentBase):
    """Sends the catalog's requests as an agent's replies would arrive (through the same conversion), then done."""

    def __init__(self, requests: list[dict[str, object]], mode: str, observes: bool) -> None:
        super().__init__()
        convert = composite_action if mode == "composite" else primitive_action
        self.plan: list[Action] = [convert(request) for request in requests] + [Done()]  # type: ignore[arg-type]
        self.observes = observes  # type: ignore[misc]

    async def act(self, observation: object, last: object) -> Action:
        return self.plan.pop(0)


@pytest.fixture(scope="module")
async def episodes(episode_runner: EpisodeRunner) -> dict[str, JobResult]:
    """One real episode per mode, on sum_two_numbers, made of the catalog's actions."""
    content = read_task(load_suite(SUITE_DIR).task(bad.TASK))
    results = {}
    for mode in ("composite", "primitive"):
        requests = [request for _, m, request, _, _ in live.ACTIONS if m == mode]
        observation = ObservationSettings(ocr="none") if mode == "primitive" else None
        (job,) = plan_jobs(
            EpisodeMatrix(
                models=[None],
                modes=[mode],
                agent="noop",
                tasks=[content],
                seeds=[0],
                max_steps=50,
                observation=observation,
            )
        )  # type: ignore[list-item]
        agent = Scripted(requests, mode, observes=mode == "primitive")
        results[mode] = await episode_runner.run(worker_job(job, 1, 600), content.payload, agent)  # type: ignore[arg-type]
    return results


@pytest.mark.parametrize(
    ("mode", "request_", "code", "fragment"), [a[1:] for a in live.ACTIONS], ids=[a[0] for a in live.ACTIONS]
)
def test_a_bad_action_costs_a_step_with_a_one_line_error(
    episodes: dict[str, JobResult], mode: str, request_: dict[str, object], code: str, fragment: str
) -> None:
    result = episodes[mode]
    assert result.outcome == "failed" and result.error_class is None, result.error_message  # judged, not crashed
    assert result.stop_reason == "done" and result.evaluation is not None
    index = [r for _, m, r, _, _ in live.ACTIONS if m == mode].index(request_)
    step: StepRecord = result.steps[index]
    assert (step.ok, step.error_code) == (False, code), step
    assert step.error_message is not None and fragment in step.error_message, step.error_message
    assert "\n" not in step.error_message and len(step.error_message) < 1000
    assert len(json.dumps(step.args)) < 20_000  # a 5 MB payload is logged by its size
    assert bad.CANARY not in "".join(step.model_dump_json() for step in result.steps)  # what trajectories hold
