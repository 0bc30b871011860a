"""The audit report of run directories: each variant's verdict counted per category, task, test and operator, the
findings listed, the vacuous graders named (from the goldens' rows), and each hole matched against the suite's
declarations (``_declarations``, read as the run's config names them) to tell explained holes from the others.

A mutant every test passes is compared with the golden by behaviour (``workers.kinds.audit``): the tests' own run
and the task's exploration. The golden's behaviour in every run makes it equivalent (left out of the score), a
difference only answers the instruction rules out show puts it outside the task (left out too), any other
difference makes it a hole, with the first difference and the run that showed it as evidence. A hole a
declaration explains is listed apart and not scored: the score is killed / (killed + unexplained holes).
"""

from __future__ import annotations

import json
from collections import Counter, defaultdict
from collections.abc import Sequence
from pathlib import Path
from urllib.parse import quote

from pydantic import ValidationError

from scratchworld_dist._errors import RunDirError
from scratchworld_dist.kinds.audit._declarations import HoleFacts, TaskDeclarations, suite_declarations
from scratchworld_dist.kinds.audit._plan import AuditSweep
from scratchworld_dist.kinds.audit._report_model import (
    AuditReport,
    Finding,
    Tally,
    TaskAudit,
    TestAudit,
    VacuousGrader,
)
from scratchworld_dist.kinds.audit._rows import AuditRow
from scratchworld_dist.reports import load_runs, read_rows
from scratchworld_dist.results import effective_rows, read_manifest
from scratchworld_dist.suites import load_suite
from scratchworld_dist.sweep import SweepConfig
from workers.contract import ScratchWorldError
from workers.kinds.audit import GraderCheck, ShownBy

__all__ = ["AuditReport", "build_audit_report", "job_page", "run_declarations", "viewer_page"]


def run_declarations(run_dir: Path) -> dict[str, TaskDeclarations]:
    """The declarations of the suite a run audited, as its config names them (``ScratchWorldError`` when the
    suite or the file cannot be read now)."""
    manifest = read_manifest(run_dir)
    if manifest is None:
        raise RunDirError(f"{run_dir}: no manifest")
    try:
        config = SweepConfig.model_validate(manifest.config)
    except ValidationError as exc:
        raise RunDirError(f"{run_dir}: its config no longer reads") from exc
    suite = load_suite(config.suite, task_list=config.tasks.task_list)
    return suite_declarations(suite, config.section("audit", AuditSweep).explanations)


def _explanation(row: AuditRow, declarations: dict[str, TaskDeclarations]) -> str | None:
    declared = declarations.get(row.task_id)
    if declared is None or row.verdict != "hole":
        return None
    first = json.loads(row.first_difference) if row.first_difference else {}
    facts = HoleFacts(
        operator=row.operator, target=row.target, block_id=row.block_id, block_opcode=row.block_opcode or "",
        change=row.change or "", difference=first.get("field"), variable=first.get("variable"),
    )  # fmt: skip
    entry = declared.explanation(facts)
    return None if entry is None else f"{entry.reason} ({declared.source})"


def _vacuous(row: AuditRow) -> VacuousGrader | None:
    if row.variant != "golden" or row.vacuous is None:
        return None
    check = GraderCheck.model_validate_json(row.grader) if row.grader else None
    return VacuousGrader(
        task_id=row.task_id,
        vacuous=row.vacuous,
        reads=check.reads if check else [],
        changes=check.changes if check else [],
    )


def _finding(row: AuditRow, failing: list[str], explanation: str | None, run: int) -> Finding:
    return Finding(
        task_id=row.task_id, job_id=row.job_id, operator=row.operator, target=row.target,
        block_id=row.block_id, description=row.description, before=row.before, after=row.after,
        failing_tests=failing, observed=row.observed, evidence=row.evidence,
        shown_by=ShownBy.model_validate_json(row.shown_by) if row.shown_by else None,
        first_difference=json.loads(row.first_difference) if row.first_difference else None,
        explanation=explanation, page=viewer_page(run, row.job_id),
    )  # fmt: skip


def build_audit_report(run_dirs: Sequence[Path], *, force: bool = False) -> AuditReport:
    """The audit of ``run_dirs`` at each job's effective attempt (``RunDirError`` when they hold no audit job)."""
    loaded, warnings = load_runs(list(run_dirs), force=force)
    counted = {(row.job_id, row.attempt) for run in loaded for row in effective_rows(run.rows)}
    found = [
        (index, row)
        for index, run in enumerate(loaded)
        for row in read_rows(run.path, "audits", AuditRow, "an audit")
        if (row.job_id, row.attempt) in counted
    ]
    run_of = {row.job_id: index for index, row in found}
    category = {row.task_id: row.category for run in loaded for row in run.rows}
    rows = [row for _, row in found]
    if not rows:
        raise RunDirError(f"{', '.join(str(run.path) for run in loaded)}: no audit results")
    declarations: list[dict[str, TaskDeclarations]] = []
    for run in loaded:
        try:
            declarations.append(run_declarations(run.path))
        except ScratchWorldError as exc:
            warnings.append(f"{run.name}: the suite's declarations cannot be read, no hole is explained: {exc}")
            declarations.append({})
    goldens = [row for row in rows if row.variant == "golden"]
    warnings += [
        f"{row.task_id}: the golden fails its own tests ({', '.join(json.loads(row.failing_tests))}): its variants'"
        " verdicts do not measure the grader"
        for row in goldens
        if row.verdict == "golden_fails"
    ]
    unmeasured = {row.task_id for row in goldens if row.verdict == "golden_fails"}
    vacuous = {grader.task_id: grader for row in goldens if (grader := _vacuous(row)) is not None}
    rows = [row for row in rows if row.variant != "golden"]
    total, tasks, operators, categories = Tally(), defaultdict(Tally), defaultdict(Tally), defaultdict(Tally)
    kills: Counter[tuple[str, str]] = Counter()
    breaks: Counter[tuple[str, str]] = Counter()
    findings: dict[str, list[Finding]] = defaultdict(list)
    for row in sorted(rows, key=lambda r: (r.task_id, r.variant, r.operator, r.job_id)):
        explanation = _explanation(row, declarations[run_of[row.job_id]])
        tasks[row.task_id].add(row.variant, row.verdict, explanation is not None)
        if row.task_id in unmeasured:
            continue  # its golden fails: nothing here says whether the tests are sound
        for tally in (total, operators[f"{row.variant}:{row.operator}"], categories[category.get(row.task_id, "")]):
            tally.add(row.variant, row.verdict, explanation is not None)
        failing = json.loads(row.failing_tests)
        for test in failing:
            (kills if row.variant == "mutant" else breaks)[(row.task_id, test)] += 1
        kind = "explained" if explanation is not None else row.verdict
        if kind in ("hole", "survived", "explained", "outside_task", "equivalent", "brittle"):
            findings[kind].append(_finding(row, failing, explanation, run_of[row.job_id]))
    tests = [
        TestAudit(task_id=task, test=test, kills=kills[(task, test)], brittle=breaks[(task, test)])
        for task, test in sorted(set(kills) | set(breaks))
    ]
    return AuditReport(
        runs=[run.name for run in loaded], warnings=warnings, total=total, mutation_score=total.mutation_score,
        refactoring_pass_rate=total.refactoring_pass_rate,
        categories={name: categories[name] for name in sorted(categories, key=_category_order)},
        vacuous=[vacuous[task] for task in sorted(vacuous) if task not in unmeasured],
        tasks=[
            TaskAudit(
                task_id=task, category=category.get(task, ""), golden_fails=task in unmeasured,
                vacuous=vacuous[task].vacuous if task in vacuous else None, **tally.model_dump(),
            )
            for task, tally in sorted(tasks.items())
        ],
        tests=tests, operators=dict(sorted(operators.items())), holes=findings["hole"] + findings["survived"],
        explained=findings["explained"], outside_task=findings["outside_task"], equivalent=findings["equivalent"],
        brittle=findings["brittle"],
    )  # fmt: skip


def _category_order(name: str) -> tuple[int, str]:
    order = ("create", "debug", "extend", "compute")
    return (order.index(name) if name in order else len(order), name)


def job_page(job_id: str) -> str:
    """A job's page in the viewer, relative to its run's page (the site's layout: ``scratchworld_dist.viewer``)."""
    return f"jobs/{quote(job_id, safe='')}.html"


def viewer_page(run: int, job_id: str) -> str:
    """A job's page in the viewer, relative to its root."""
    return f"runs/{run}/{job_page(job_id)}"
