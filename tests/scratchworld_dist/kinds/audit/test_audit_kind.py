"""The grader audit as a job kind, end to end on a hand-made task with two planted weaknesses: a test that
accepts any greeting (a grader hole: a mutant of the greeting survives) and a test that finds the score by
its variable's name (brittle: renaming the variable, which changes no behaviour, fails it). The audit runs as
a sweep (``scratchworld audit``, once for the module), lands in its own table, reports both, resumes, and its
findings link to viewer pages that show the golden and the variant. The golden's texts are markup, as a
hostile project's could be."""

from __future__ import annotations

import json
import shutil
from dataclasses import dataclass
from html import escape
from pathlib import Path

import pyarrow as pa
import pyarrow.compute as pc
import pyarrow.parquet as pq
import pytest
from pydantic import ValidationError

from scratchworld_dist.kinds.audit import AuditSweep, build_audit_report, render_audit, task_variants
from scratchworld_dist.kinds.tasks import read_task
from scratchworld_dist.results import RunStore
from scratchworld_dist.sb3 import Project, block, rect_costume
from scratchworld_dist.suites import load_suite
from scratchworld_dist.sweep import plan_run, sweep_config_from, worker_job
from scratchworld_dist.viewer import ViewerSite
from tests.conftest import SUITE_DIR
from tests.support.cli_runner import Done, invoke
from tests.support.small_suites import TASK_DIR, upstream_clone
from workers.contract import AgentJob, JobHeader
from workers.kinds.audit import AuditSpec

GREETING = '<script>alert("Hello")</script>'
"""What the golden's greeter says: markup that must reach every page as text."""

LOOSE = "<img src=x onerror=alert(1)>"
"""A loose stage block's value (no hat: it never runs, and no variant changes it), listed on every page."""

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


def greeter(done: bool, greeting: str = GREETING) -> bytes:
    project = Project()
    project.stage.variable("score", 0)
    project.stage.script(block("data_setvariableto", VARIABLE="score", VALUE=LOOSE), x=400, y=300)
    sprite = project.sprite("Greeter", costume=rect_costume("box", 20, 20, "#33aa55"))
    if done:
        sprite.script(
            block("event_whenflagclicked"),
            block("data_setvariableto", VARIABLE="score", VALUE=10),
            block("looks_say", MESSAGE=greeting),
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


@dataclass(frozen=True)
class Audited:
    args: list[str]
    out: Path
    figures: Path
    done: Done


@pytest.fixture(scope="module")
def audited(weak_suite: Path, tmp_path_factory: pytest.TempPathFactory, shared_ray: int) -> Audited:
    """The weak suite audited once (``scratchworld audit``) for the module's tests."""
    folder = tmp_path_factory.mktemp("audit")
    out, figures = folder / "audit", folder / "audit.json"
    args = ["audit", str(weak_suite), "--out", str(out), "--json", str(figures)]
    return Audited(args, out, figures, invoke(*args))


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


def test_an_audit_job_is_sent_its_header_and_variant_and_refuses_agent_fields(weak_suite: Path, tmp_path: Path) -> None:
    """No agent acts in an audit: the worker is sent no agent, model, seed or model settings, and its spec takes
    none, so no code can come to read them."""
    section = {"mutants_per_task": 1, "refactorings_per_task": 0}
    data = {"name": "a", "benchmark": "audit", "suite": str(weak_suite), "audit": section, "output": str(tmp_path)}
    job = plan_run(sweep_config_from(data, tmp_path), notice=lambda message: None).jobs[-1]
    sent = worker_job(job, 2, 60)
    assert isinstance(sent, AuditSpec) and isinstance(sent, JobHeader) and not isinstance(sent, AgentJob)
    assert set(sent.model_dump()) == {
        *JobHeader.model_fields,
        "variant",
        "project_json",
        "project_limits",
        "exploration",
        "stop_at_first_failure",
    }
    assert sent.exploration is not None and sent.exploration.episodes  # the task's exploration, as planned
    assert (sent.job_id, sent.attempt, sent.timeout_s, sent.harness) == (job.job_id, 2, 60, job.harness)
    with pytest.raises(ValidationError) as caught:
        AuditSpec(**job.agent_header(2, 60), variant=sent.variant, project_json=sent.project_json)
    refused = {str(error["loc"][0]): error["type"] for error in caught.value.errors()}
    assert refused == dict.fromkeys(("agent", "agent_code", "model", "seed", "llm", "model_cache"), "extra_forbidden")


@pytest.mark.ray
@pytest.mark.browser
def test_the_audit_finds_the_planted_hole_and_the_brittle_test_and_resumes(audited: Audited) -> None:
    out, figures, done = audited.out, audited.figures, audited.done
    assert done.returncode == 0, done.stderr
    rows = RunStore(out).read_table("audits").to_pylist()
    verdicts = {(row["variant"], row["operator"], row["verdict"]) for row in rows}
    # The hole: a changed greeting is still "something", and the traces show the bubble differs.
    holes = [row for row in rows if row["verdict"] == "hole"]
    assert holes and {row["operator"] for row in holes} == {"text_literal"}
    assert all("Greeter, bubble" in row["evidence"] and row["observed"] == "differs" for row in holes)
    assert ("mutant", "number_literal", "killed") in verdicts
    # A mutant the first test kills stops there (the second is not run); only killed mutants stop.
    stopped = [row for row in rows if row["stopped_at"] is not None]
    assert stopped and {(row["variant"], row["verdict"]) for row in stopped} == {("mutant", "killed")}
    assert all((row["stopped_at"], row["tests_not_run"]) == ("the greeter says something", 1) for row in stopped)
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
    assert "# Grader audit" in done.stdout and "## Holes" in done.stdout and f"text {GREETING!r} ->" in done.stdout
    again = invoke(*audited.args)
    assert again.returncode == 0 and f"{len(rows)} already decided, 0 to run" in " ".join(again.stderr.split())


@pytest.mark.ray
@pytest.mark.browser
def test_findings_link_to_a_page_with_both_programs_the_change_and_the_evidence(
    audited: Audited, weak_suite: Path, tmp_path: Path
) -> None:
    assert audited.done.returncode == 0, audited.done.stderr
    report = build_audit_report([audited.out])
    findings = [*report.holes, *report.brittle, *report.equivalent]
    assert report.holes and report.brittle
    # The report links every finding: from the viewer's root (Markdown, HTML), and from the run's own page.
    markdown, html = render_audit(report, "md"), render_audit(report, "html")
    site = ViewerSite([audited.out])
    run_page = site.get("runs/0/index.html")
    assert run_page is not None and run_page.body is not None
    for finding in findings:
        assert finding.page == f"runs/0/jobs/{finding.job_id}.html"
        assert f"](<{finding.page}>)" in markdown and f'<a href="{finding.page}">' in html
        assert f'<a href="jobs/{finding.job_id}.html">' in run_page.body.decode()
    assert "<script>" not in html and escape(GREETING) in html

    hole = report.holes[0]
    page = site.get(hole.page)
    assert page is not None and page.body is not None
    text = page.body.decode()
    # The evidence first, then the verdict and both programs in full: the loose stage script no variant touched
    # is listed in each column, and the changed greeting is marked in each.
    assert hole.evidence and GREETING in hole.evidence
    evidence = text.index('class="audit-evidence"')
    assert escape(hole.evidence) in text[evidence : text.index("</p>", evidence)]
    assert evidence < text.index('class="badge failed">hole<') < text.index("audit-programs")
    assert "<th>golden</th><th>mutant: text_literal</th>" in text
    assert text.count(escape(json.dumps(LOOSE))) == 2
    marked = [part.split("</mark>")[0] for part in text.split('<mark class="changed-block"')[1:]]
    assert len(marked) == 2 and escape(json.dumps(GREETING)) in marked[0] and "looks_say" in marked[1]
    assert escape(json.dumps(GREETING)) not in marked[1]  # the mutant's greeting differs from the golden's
    assert "<script>" not in text and "<img" not in text  # hostile text arrives as text only

    # The golden's own page lists it alone; a run whose suite is gone or changed shows the change as recorded.
    (golden_row,) = [r for r in RunStore(audited.out).read_table("audits").to_pylist() if r["variant"] == "golden"]
    golden_page = site.get(f"runs/0/jobs/{golden_row['job_id']}.html")
    assert golden_page is not None and golden_page.body is not None
    assert "<h4>The golden</h4>" in golden_page.body.decode() and "columns-1" in golden_page.body.decode()
    changed_suite = tmp_path / "suite"
    shutil.copytree(weak_suite, changed_suite)
    (changed_suite / "create" / "greeter" / "golden.sb3").write_bytes(greeter(True, "Bye"))
    for suite, why in ((tmp_path / "gone", "cannot be read as it was planned"), (changed_suite, "changed since")):
        moved = tmp_path / f"run-{suite.name}"
        shutil.copytree(audited.out, moved)
        manifest = json.loads((moved / "manifest.json").read_text())
        manifest["config"]["suite"] = str(suite)
        (moved / "manifest.json").write_text(json.dumps(manifest))
        shown = ViewerSite([moved]).get(hole.page)
        assert shown is not None and shown.body is not None
        body = shown.body.decode()
        assert "Programs not shown" in body and why in body and "audit-programs" not in body
        assert escape(hole.before) in body and escape(hole.evidence) in body


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


@pytest.mark.ray
@pytest.mark.browser
def test_a_task_whose_golden_fails_is_shown_but_not_counted(audited: Audited, tmp_path: Path) -> None:
    report = build_audit_report([audited.out])
    assert list(report.categories) == ["create"] and report.categories["create"] == report.total
    (task,) = report.tasks
    assert task.category == "create" and not task.golden_fails and report.total.mutants == task.mutants > 0
    # The same run, had its golden failed its own tests: the task is listed with its verdicts, flagged, and no
    # suite figure counts them (they say nothing of the tests).
    failed = tmp_path / "failed"
    shutil.copytree(audited.out, failed)
    for shard in (failed / "audits").glob("*.parquet"):
        table = pq.read_table(shard)
        golden = pc.equal(table["variant"], "golden")
        verdicts = pc.if_else(golden, pa.scalar("golden_fails"), table["verdict"])
        pq.write_table(table.set_column(table.schema.get_field_index("verdict"), "verdict", verdicts), shard)
    flagged = build_audit_report([failed])
    (task,) = flagged.tasks
    assert task.golden_fails and task.mutants == report.total.mutants
    assert flagged.total.mutants == 0 and flagged.mutation_score is None and flagged.categories == {}
    assert flagged.holes == [] and flagged.brittle == [] and any("golden fails" in w for w in flagged.warnings)
    assert "(golden fails: not counted)" in render_audit(flagged, "md")
