"""The audit report: how often each task's tests fail a wrong program (mutation score) and pass a correct one
written differently (refactoring pass rate), per task, per test and per operator, with every survivor and
every brittle case listed (its change as pseudocode, the tests that passed or failed it).

A survivor is not yet told apart from an equivalent mutant (that needs the observable traces of both
programs): the mutation score here is killed / (killed + survived), a lower bound of killed / (killed + holes).
"""

from __future__ import annotations

import json
from collections import Counter, defaultdict
from collections.abc import Sequence
from pathlib import Path

from pydantic import BaseModel

from scratchworld_dist._errors import RunDirError
from scratchworld_dist.kinds.audit._rows import AuditRow
from scratchworld_dist.reports import Block as ReportBlock
from scratchworld_dist.reports import Heading, Paragraph, Table, blocks_html, blocks_markdown, load_runs, read_rows
from scratchworld_dist.results import effective_rows


class Tally(BaseModel):
    mutants: int = 0
    killed: int = 0
    survived: int = 0
    refactorings: int = 0
    passed: int = 0
    brittle: int = 0
    errors: int = 0

    @property
    def mutation_score(self) -> float | None:
        decided = self.killed + self.survived
        return self.killed / decided if decided else None

    @property
    def refactoring_pass_rate(self) -> float | None:
        decided = self.passed + self.brittle
        return self.passed / decided if decided else None

    def add(self, row: AuditRow) -> None:
        if row.variant == "mutant":
            self.mutants += 1
        else:
            self.refactorings += 1
        verdict = row.verdict
        if verdict in ("killed", "survived", "passed", "brittle", "errors"):
            setattr(self, verdict, getattr(self, verdict) + 1)
        elif verdict == "error":
            self.errors += 1


class TaskAudit(Tally):
    task_id: str


class TestAudit(BaseModel):
    """One test of one task: the mutants it failed, and the refactorings it failed (wrongly)."""

    task_id: str
    test: str
    kills: int
    brittle: int


class Finding(BaseModel):
    """A survivor or a brittle case, with what changed and where."""

    task_id: str
    job_id: str
    operator: str
    target: str
    block_id: str
    description: str
    before: str
    after: str
    failing_tests: list[str]


class AuditReport(BaseModel):
    runs: list[str]
    warnings: list[str]
    total: Tally
    mutation_score: float | None
    """killed / (killed + survived) over the suite (a lower bound until survivors are told from equivalents)."""

    refactoring_pass_rate: float | None
    tasks: list[TaskAudit]
    tests: list[TestAudit]
    operators: dict[str, Tally]
    survivors: list[Finding]
    brittle: list[Finding]


def build_audit_report(run_dirs: Sequence[Path], *, force: bool = False) -> AuditReport:
    """The audit of ``run_dirs`` at each job's effective attempt (``RunDirError`` when they hold no audit job)."""
    loaded, warnings = load_runs(list(run_dirs), force=force)
    counted = {(row.job_id, row.attempt) for run in loaded for row in effective_rows(run.rows)}
    rows = [
        row
        for run in loaded
        for row in read_rows(run.path, "audits", AuditRow, "an audit")
        if (row.job_id, row.attempt) in counted
    ]
    if not rows:
        raise RunDirError(f"{', '.join(str(run.path) for run in loaded)}: no audit results")
    goldens = [row for row in rows if row.variant == "golden"]
    warnings += [
        f"{row.task_id}: the golden fails its own tests ({', '.join(json.loads(row.failing_tests))}): its variants'"
        " verdicts do not measure the grader"
        for row in goldens
        if row.verdict == "golden_fails"
    ]
    rows = [row for row in rows if row.variant != "golden"]
    total, tasks, operators = Tally(), defaultdict(Tally), defaultdict(Tally)
    kills: Counter[tuple[str, str]] = Counter()
    breaks: Counter[tuple[str, str]] = Counter()
    survivors, brittle = [], []
    for row in sorted(rows, key=lambda r: (r.task_id, r.variant, r.operator, r.job_id)):
        for tally in (total, tasks[row.task_id], operators[f"{row.variant}:{row.operator}"]):
            tally.add(row)
        failing = json.loads(row.failing_tests)
        for test in failing:
            (kills if row.variant == "mutant" else breaks)[(row.task_id, test)] += 1
        if row.verdict in ("survived", "brittle"):
            finding = Finding(
                task_id=row.task_id, job_id=row.job_id, operator=row.operator, target=row.target,
                block_id=row.block_id, description=row.description, before=row.before, after=row.after,
                failing_tests=failing,
            )  # fmt: skip
            (survivors if row.verdict == "survived" else brittle).append(finding)
    tests = [
        TestAudit(task_id=task, test=test, kills=kills[(task, test)], brittle=breaks[(task, test)])
        for task, test in sorted(set(kills) | set(breaks))
    ]
    return AuditReport(
        runs=[run.name for run in loaded], warnings=warnings, total=total, mutation_score=total.mutation_score,
        refactoring_pass_rate=total.refactoring_pass_rate,
        tasks=[TaskAudit(task_id=task, **tally.model_dump()) for task, tally in sorted(tasks.items())],
        tests=tests, operators=dict(sorted(operators.items())), survivors=survivors, brittle=brittle,
    )  # fmt: skip


def _pct(value: float | None) -> str:
    return "-" if value is None else f"{100 * value:.1f}%"


def audit_blocks(report: AuditReport) -> list[ReportBlock]:
    """The report as blocks (Markdown or HTML alike)."""
    t = report.total
    blocks: list[ReportBlock] = [
        Heading(level=1, text="Grader audit"),
        Paragraph(
            text=f"Mutation score {_pct(report.mutation_score)} ({t.killed} of {t.killed + t.survived} mutants "
            f"killed; survivors not yet told from equivalent mutants, so this is a lower bound); refactoring "
            f"pass rate {_pct(report.refactoring_pass_rate)} ({t.passed} of {t.passed + t.brittle}); "
            f"{t.errors} variant(s) without a verdict."
        ),
        *(Paragraph(text=f"Warning: {warning}") for warning in report.warnings),
        Heading(level=2, text="Per task"),
        Table(
            header=["task", "mutants", "killed", "survived", "score", "refactorings", "passed", "brittle"],
            rows=[
                [
                    a.task_id,
                    str(a.mutants),
                    str(a.killed),
                    str(a.survived),
                    _pct(a.mutation_score),
                    str(a.refactorings),
                    str(a.passed),
                    str(a.brittle),
                ]
                for a in report.tasks
            ],
        ),
        Heading(level=2, text="Per operator"),
        Table(
            header=["operator", "variants", "killed", "survived", "passed", "brittle"],
            rows=[
                [name, str(o.mutants + o.refactorings), str(o.killed), str(o.survived), str(o.passed), str(o.brittle)]
                for name, o in report.operators.items()
            ],
        ),
        Heading(level=2, text="Per test"),
        Table(
            header=["task", "test", "mutants it failed", "refactorings it failed"],
            rows=[[s.task_id, s.test, str(s.kills), str(s.brittle)] for s in report.tests],
        ),
    ]
    for title, findings in (("Survivors", report.survivors), ("Brittle", report.brittle)):
        blocks.append(Heading(level=2, text=f"{title} ({len(findings)})"))
        for f in findings:
            failing = ", ".join(f.failing_tests) or "none"
            blocks.append(
                Paragraph(
                    text=f"{f.task_id} · {f.operator} at {f.target}/{f.block_id}: {f.description} "
                    f"(job {f.job_id}; failing tests: {failing})\nbefore:\n{f.before}\nafter:\n{f.after}"
                )
            )
    return blocks


def render_audit(report: AuditReport, fmt: str) -> str:
    if fmt == "json":
        return report.model_dump_json(indent=2) + "\n"
    blocks = audit_blocks(report)
    return blocks_html(blocks) if fmt == "html" else blocks_markdown(blocks)
