"""The grader audit as a job kind, end to end on a hand-made task with two planted weaknesses: a test that
accepts any greeting (a grader hole: a mutant of the greeting survives) and a test that finds the score by
its variable's name (brittle: renaming the variable, which changes no behaviour, fails it). The audit runs as
a sweep (``scratchworld audit``), lands in its own table, reports both, and resumes."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from scratchworld_dist._run_plan import plan_run
from scratchworld_dist.kinds.audit import AuditSweep, task_variants
from scratchworld_dist.kinds.tasks import read_task
from scratchworld_dist.results import RunStore
from scratchworld_dist.sb3 import Project, block, rect_costume
from scratchworld_dist.suites import load_suite
from scratchworld_dist.sweep import sweep_config_from
from tests.conftest import SUITE_DIR
from tests.support.cli_runner import invoke
from tests.support.small_suites import TASK_DIR, upstream_clone

WEAK_JS = """
module.exports = async (vm) => Harness.runTests(vm, [
  {
    name: 'the greeter says something',
    timeoutMs: 5000,
    run: async () => {
      const speech = Harness.recordSpeech(vm);
      await Harness.start(vm);
      await Harness.wait(500);
      speech.stop();
      return {passed: speech.texts('Greeter').length > 0};
    },
  },
  {
    name: 'the score is 10',
    timeoutMs: 5000,
    run: async () => {
      await Harness.start(vm);
      await Harness.wait(500);
      return {passed: Number(Harness.valueOf(vm, 'score')) === 10};
    },
  },
]);
"""


def greeter(done: bool) -> bytes:
    project = Project()
    project.stage.variable("score", 0)
    sprite = project.sprite("Greeter", costume=rect_costume("box", 20, 20, "#33aa55"))
    if done:
        sprite.script(
            block("event_whenflagclicked"),
            block("data_setvariableto", VARIABLE="score", VALUE=10),
            block("looks_say", MESSAGE="Hello"),
        )
    return project.to_sb3()


@pytest.fixture(scope="module")
def weak_suite(tmp_path_factory: pytest.TempPathFactory) -> Path:
    suite = tmp_path_factory.mktemp("weak-suite")
    for name in ("suite.json", "harness.js"):
        (suite / name).write_bytes((SUITE_DIR / name).read_bytes())
    folder = suite / "create" / "greeter"
    folder.mkdir(parents=True)
    (folder / "task.json").write_text(json.dumps({"instruction": "Greet, and keep 10 points.", "timeout_s": 20}))
    (folder / "evaluate.js").write_text(WEAK_JS)
    (folder / "golden.sb3").write_bytes(greeter(True))
    (folder / "initial.sb3").write_bytes(greeter(False))
    return suite


def test_variants_are_planned_from_the_golden_deterministically(weak_suite: Path) -> None:
    content = read_task(load_suite(weak_suite).task("greeter"))
    settings = AuditSweep(mutants_per_task=5, refactorings_per_task=2, seed=3)
    first, again = task_variants(content, settings), task_variants(content, settings)
    assert [v.project for v in first] == [v.project for v in again] and len(first) == 7
    assert len(task_variants(content, AuditSweep())) > len(first)  # no cap: every variant
    assert any(v.operator == "rename_variable" for v in task_variants(content, AuditSweep()))
    named = content.model_copy(update={"payload": content.payload.model_copy(update={"instruction": "Set score."})})
    # A variable the instruction names is part of the task: renaming it is no refactoring.
    assert not any(v.operator == "rename_variable" for v in task_variants(named, AuditSweep()))


@pytest.mark.ray
@pytest.mark.browser
def test_the_audit_finds_the_planted_hole_and_the_brittle_test_and_resumes(
    weak_suite: Path, tmp_path: Path, shared_ray: int
) -> None:
    out, figures = tmp_path / "audit", tmp_path / "audit.json"
    args = ["audit", str(weak_suite), "--out", str(out), "--json", str(figures)]
    done = invoke(*args)
    assert done.returncode == 0, done.stderr
    rows = RunStore(out).read_table("audits").to_pylist()
    verdicts = {(row["variant"], row["operator"], row["verdict"]) for row in rows}
    # The hole: a changed greeting is still "something", and the traces show the bubble differs.
    holes = [row for row in rows if row["verdict"] == "hole"]
    assert holes and {row["operator"] for row in holes} == {"text_literal"}
    assert all("Greeter, bubble" in row["evidence"] and row["observed"] == "differs" for row in holes)
    assert ("mutant", "number_literal", "killed") in verdicts
    # The brittle test: the score renamed fails "the score is 10", which looks it up by name.
    renamed = [row for row in rows if row["operator"] == "rename_variable"]
    assert renamed and all(row["verdict"] == "brittle" for row in renamed)
    assert all(json.loads(row["failing_tests"]) == ["the score is 10"] for row in renamed)
    assert ("refactoring", "move_script", "passed") in verdicts
    assert ("golden", "golden", "golden_passes") in verdicts  # so the variants measure the grader
    (task,) = json.loads(figures.read_text())
    assert task["task_id"] == "greeter" and task["holes"] == len(holes)
    assert task["killed"] + task["holes"] + task["equivalent"] == task["mutants"] > 0
    assert task["brittle"] == len(renamed) and set(task) >= {"equivalent", "holes", "refactorings"}
    assert "# Grader audit" in done.stdout and "## Holes" in done.stdout and "text 'Hello' ->" in done.stdout
    again = invoke(*args)
    assert again.returncode == 0 and f"{len(rows)} already decided, 0 to run" in " ".join(again.stderr.split())


def test_upstream_goldens_are_audited_on_the_virtual_clock_unless_the_config_says(tmp_path: Path) -> None:
    clone = upstream_clone(tmp_path / "ScratchWorld")
    (clone / "scratch-gui" / "static" / "calc_golden.sb3").write_bytes((TASK_DIR / "golden.sb3").read_bytes())
    audit = {"mutants_per_task": 2, "refactorings_per_task": 0}
    base = {"name": "a", "benchmark": "audit", "suite": str(clone), "audit": audit}

    def clocks(**fields: object) -> set[str]:
        plan = plan_run(sweep_config_from({**base, **fields}, tmp_path), notice=lambda _: None)
        assert len(plan.jobs) == 3  # the golden and two mutants
        return {content.payload.evaluation.clock for content in plan.contents}

    # An upstream clone's episodes default to the real clock; its audit does not (verdicts would follow load).
    assert clocks() == {"virtual"}
    assert clocks(clock="real") == {"real"}
