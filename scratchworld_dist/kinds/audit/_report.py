"""The audit report: how often each task's tests fail a wrong program (mutation score) and pass a correct one
written differently (refactoring pass rate), per task, per test and per operator, with every survivor and
every brittle case listed (its change as pseudocode, the tests that passed or failed it).

A mutant every test passes is traced with the golden under one seed (``workers.kinds.audit``): the same
observable trace makes it equivalent (no test can tell it apart, so it is left out of the score), another
makes it a hole, with the first observable difference as evidence. The score is killed / (killed + holes).
"""

from __future__ import annotations

import json
from collections import Counter, defaultdict
from collections.abc import Callable, Sequence
from pathlib import Path
from urllib.parse import quote

from pydantic import BaseModel

from scratchworld_dist._errors import RunDirError
from scratchworld_dist.kinds.audit._rows import AuditRow
from scratchworld_dist.reports import Block as ReportBlock
from scratchworld_dist.reports import (
    Code,
    Heading,
    Linked,
    Paragraph,
    Table,
    blocks_html,
    blocks_markdown,
    load_runs,
    read_rows,
)
from scratchworld_dist.results import effective_rows


class Tally(BaseModel):
    mutants: int = 0
    killed: int = 0
    equivalent: int = 0
    holes: int = 0
    survived: int = 0
    """Passed every test and could not be traced (counted as holes by the score: a lower bound)."""

    refactorings: int = 0
    passed: int = 0
    brittle: int = 0
    errors: int = 0

    @property
    def mutation_score(self) -> float | None:
        """killed / (killed + holes): equivalent mutants can be killed by no test, untraced survivors count as holes."""
        decided = self.killed + self.holes + self.survived
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
        field = {"hole": "holes", "error": "errors"}.get(verdict, verdict)
        if field in ("killed", "equivalent", "holes", "survived", "passed", "brittle", "errors"):
            setattr(self, field, getattr(self, field) + 1)


class TaskAudit(Tally):
    task_id: str
    category: str = ""
    golden_fails: bool = False
    """Its golden fails its own tests: its variants' verdicts measure nothing, and no suite figure counts them."""


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
    observed: str | None
    evidence: str | None
    page: str
    """Its job's page in the viewer of these runs (``scratchworld view`` with the runs in this order), relative to
    the viewer's root: ``runs/<k>/jobs/<job_id>.html``. The page shows the golden and the variant side by side."""


class AuditReport(BaseModel):
    runs: list[str]
    warnings: list[str]
    total: Tally
    mutation_score: float | None
    """killed / (killed + holes) over the suite (an untraced survivor counts as a hole)."""

    refactoring_pass_rate: float | None
    categories: dict[str, Tally] = {}
    """The same figures per task category (create, debug, ...), over the tasks whose golden passes."""

    tasks: list[TaskAudit]
    tests: list[TestAudit]
    operators: dict[str, Tally]
    holes: list[Finding]
    """Mutants every test passed whose behaviour differs from the golden's (and untraced survivors)."""

    equivalent: list[Finding]
    brittle: list[Finding]


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
    goldens = [row for row in rows if row.variant == "golden"]
    warnings += [
        f"{row.task_id}: the golden fails its own tests ({', '.join(json.loads(row.failing_tests))}): its variants'"
        " verdicts do not measure the grader"
        for row in goldens
        if row.verdict == "golden_fails"
    ]
    unmeasured = {row.task_id for row in goldens if row.verdict == "golden_fails"}
    rows = [row for row in rows if row.variant != "golden"]
    total, tasks, operators, categories = Tally(), defaultdict(Tally), defaultdict(Tally), defaultdict(Tally)
    kills: Counter[tuple[str, str]] = Counter()
    breaks: Counter[tuple[str, str]] = Counter()
    findings: dict[str, list[Finding]] = {"hole": [], "survived": [], "equivalent": [], "brittle": []}
    for row in sorted(rows, key=lambda r: (r.task_id, r.variant, r.operator, r.job_id)):
        tasks[row.task_id].add(row)
        if row.task_id in unmeasured:
            continue  # its golden fails: nothing here says whether the tests are sound
        for tally in (total, operators[f"{row.variant}:{row.operator}"], categories[category.get(row.task_id, "")]):
            tally.add(row)
        failing = json.loads(row.failing_tests)
        for test in failing:
            (kills if row.variant == "mutant" else breaks)[(row.task_id, test)] += 1
        if row.verdict in findings:
            findings[row.verdict].append(
                Finding(
                    task_id=row.task_id, job_id=row.job_id, operator=row.operator, target=row.target,
                    block_id=row.block_id, description=row.description, before=row.before, after=row.after,
                    failing_tests=failing, observed=row.observed, evidence=row.evidence,
                    page=viewer_page(run_of[row.job_id], row.job_id),
                )
            )  # fmt: skip
    tests = [
        TestAudit(task_id=task, test=test, kills=kills[(task, test)], brittle=breaks[(task, test)])
        for task, test in sorted(set(kills) | set(breaks))
    ]
    return AuditReport(
        runs=[run.name for run in loaded], warnings=warnings, total=total, mutation_score=total.mutation_score,
        refactoring_pass_rate=total.refactoring_pass_rate,
        categories={name: categories[name] for name in sorted(categories, key=_category_order)},
        tasks=[
            TaskAudit(
                task_id=task, category=category.get(task, ""), golden_fails=task in unmeasured, **tally.model_dump()
            )
            for task, tally in sorted(tasks.items())
        ],
        tests=tests, operators=dict(sorted(operators.items())), holes=findings["hole"] + findings["survived"],
        equivalent=findings["equivalent"], brittle=findings["brittle"],
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


def _pct(value: float | None) -> str:
    return "-" if value is None else f"{100 * value:.1f}%"


def audit_blocks(report: AuditReport, link: Callable[[Finding], str] | None = None) -> list[ReportBlock]:
    """The report as blocks (Markdown or HTML alike); each finding links to ``link(finding)`` (default: its
    ``page``, relative to the viewer's root)."""
    href = link or (lambda finding: finding.page)
    t = report.total
    untraced = f", {t.survived} survivor(s) not traced, counted as holes" if t.survived else ""
    blocks: list[ReportBlock] = [
        Heading(level=1, text="Grader audit"),
        Paragraph(
            text=f"Mutation score {_pct(report.mutation_score)}: {t.killed} mutants killed, {t.holes} holes (a "
            f"mutant every test passes that behaves otherwise than the golden){untraced}; {t.equivalent} "
            f"equivalent (the golden's observable trace, which no test can tell apart) left out. Refactoring pass "
            f"rate {_pct(report.refactoring_pass_rate)} ({t.passed} of {t.passed + t.brittle}); {t.errors} "
            "variant(s) without a verdict."
        ),
        *(Paragraph(text=f"Warning: {warning}") for warning in report.warnings),
        Heading(level=2, text="Per category"),
        Table(
            header=[
                "category",
                "mutants",
                "killed",
                "equivalent",
                "holes",
                "score",
                "refactorings",
                "passed",
                "brittle",
            ],
            rows=[[name or "-", *_figures(c)] for name, c in report.categories.items()],
        ),
        Heading(level=2, text="Per task"),
        Table(
            header=["task", "mutants", "killed", "equivalent", "holes", "score", "refactorings", "passed", "brittle"],
            rows=[
                [a.task_id + (" (golden fails: not counted)" if a.golden_fails else ""), *_figures(a)]
                for a in report.tasks
            ],
        ),
        Heading(level=2, text="Per operator"),
        Table(
            header=["operator", "variants", "killed", "equivalent", "holes", "passed", "brittle"],
            rows=[
                [
                    name,
                    str(o.mutants + o.refactorings),
                    str(o.killed),
                    str(o.equivalent),
                    str(o.holes + o.survived),
                    str(o.passed),
                    str(o.brittle),
                ]
                for name, o in report.operators.items()
            ],
        ),
        Heading(level=2, text="Per test"),
        Table(
            header=["task", "test", "mutants it failed", "refactorings it failed"],
            rows=[[s.task_id, s.test, str(s.kills), str(s.brittle)] for s in report.tests],
        ),
    ]
    if report.holes or report.brittle or report.equivalent:
        where = "" if link is not None else " (paths under the viewer of these runs: `scratchworld view RUN_DIR...`)"
        blocks.append(
            Paragraph(
                text=f"Each finding links to its job's page{where}: the golden and the variant side by side, every "
                "script, the change marked, with the verdict and the first observable difference."
            )
        )
    for title, findings in (("Holes", report.holes), ("Brittle", report.brittle), ("Equivalent", report.equivalent)):
        blocks.append(Heading(level=2, text=f"{title} ({len(findings)})"))
        for f in findings:
            failing = ", ".join(f.failing_tests) or "none"
            seen = f"; first observable difference: {f.evidence}" if f.evidence else ""
            blocks.append(
                Linked(
                    text=f"{f.task_id} · {f.operator} at {f.target}/{f.block_id}: {f.description} "
                    f"(job {f.job_id}; failing tests: {failing}{seen})",
                    label="golden and variant side by side",
                    href=href(f),
                )
            )
            blocks.append(Code(text=f"before:\n{f.before}\n\nafter:\n{f.after}"))
    return blocks


def _figures(t: Tally) -> list[str]:
    """mutants, killed, equivalent, holes, score, refactorings, passed, brittle."""
    counts = (t.mutants, t.killed, t.equivalent, t.holes + t.survived)
    return [*map(str, counts), _pct(t.mutation_score), *map(str, (t.refactorings, t.passed, t.brittle))]


def render_audit(report: AuditReport, fmt: str, link: Callable[[Finding], str] | None = None) -> str:
    """The report in ``fmt``; ``link``: where a finding's page is from where the report is read (default: its
    ``page``, from the viewer's root)."""
    if fmt == "json":
        return report.model_dump_json(indent=2) + "\n"
    blocks = audit_blocks(report, link)
    return blocks_html(blocks) if fmt == "html" else blocks_markdown(blocks)
