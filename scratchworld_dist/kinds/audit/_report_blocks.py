"""The audit report as text: Markdown, HTML (the same blocks) or JSON. Vacuous graders come first, before any
score; each finding links to its job's page in the viewer."""

from __future__ import annotations

from collections.abc import Callable

from scratchworld_dist.kinds.audit._report_model import AuditReport, Finding, Tally
from scratchworld_dist.reports import Block as ReportBlock
from scratchworld_dist.reports import Code, Heading, Linked, Paragraph, Table, blocks_html, blocks_markdown

FIGURES = ["mutants", "killed", "equivalent", "outside task", "holes", "explained", "score"]
REFACTORING_FIGURES = ["refactorings", "passed", "brittle"]


def _pct(value: float | None) -> str:
    return "-" if value is None else f"{100 * value:.1f}%"


def _figures(t: Tally) -> list[str]:
    """mutants, killed, equivalent, outside task, holes (unexplained, untraced survivors too), explained, score,
    refactorings, passed, brittle."""
    counts = (t.mutants, t.killed, t.equivalent, t.outside_task, t.holes + t.survived, t.explained)
    return [*map(str, counts), _pct(t.mutation_score), *map(str, (t.refactorings, t.passed, t.brittle))]


def _summary(report: AuditReport) -> str:
    t = report.total
    untraced = f", {t.survived} survivor(s) not traced, counted as holes" if t.survived else ""
    return (
        f"Mutation score {_pct(report.mutation_score)}: {t.killed} mutants killed, {t.holes} unexplained holes (a "
        f"mutant every test passes that behaves otherwise than the golden in a run the task allows){untraced}; left "
        f"out: {t.explained} explained holes (the suite declares the difference open), {t.outside_task} outside the "
        f"task (they differ only under answers the instruction rules out), {t.equivalent} equivalent (the golden's "
        "trace in the tests' own run and in every run of the task's exploration). Refactoring pass rate "
        f"{_pct(report.refactoring_pass_rate)} ({t.passed} of {t.passed + t.brittle}); {t.errors} variant(s) without "
        "a verdict."
    )


def _finding_blocks(title: str, findings: list[Finding], href: Callable[[Finding], str]) -> list[ReportBlock]:
    blocks: list[ReportBlock] = [Heading(level=2, text=f"{title} ({len(findings)})")]
    for f in findings:
        failing = ", ".join(f.failing_tests) or "none"
        seen = f"; first observable difference: {f.evidence}" if f.evidence else ""
        shown = f", shown by {f.shown_by.describe()}" if f.shown_by and f.evidence else ""
        why = f"; explained: {f.explanation}" if f.explanation else ""
        blocks.append(
            Linked(
                text=f"{f.task_id} · {f.operator} at {f.target}/{f.block_id}: {f.description} "
                f"(job {f.job_id}; failing tests: {failing}{seen}{shown}{why})",
                label="golden and variant side by side",
                href=href(f),
            )
        )
        blocks.append(Code(text=f"before:\n{f.before}\n\nafter:\n{f.after}"))
    return blocks


def audit_blocks(report: AuditReport, link: Callable[[Finding], str] | None = None) -> list[ReportBlock]:
    """The report as blocks (Markdown or HTML alike); each finding links to ``link(finding)`` (default: its
    ``page``, relative to the viewer's root)."""
    href = link or (lambda finding: finding.page)
    blocks: list[ReportBlock] = [Heading(level=1, text="Grader audit")]
    if report.vacuous:
        blocks.append(Heading(level=2, text=f"Vacuous graders ({len(report.vacuous)})"))
        blocks += [
            Paragraph(
                text=f"{grader.task_id}: {grader.vacuous}: {grader.describe()}; it passes any program, so its "
                "score below measures nothing."
            )
            for grader in report.vacuous
        ]
    blocks += [
        Paragraph(text=_summary(report)),
        *(Paragraph(text=f"Warning: {warning}") for warning in report.warnings),
        Heading(level=2, text="Per category"),
        Table(
            header=["category", *FIGURES, *REFACTORING_FIGURES],
            rows=[[name or "-", *_figures(c)] for name, c in report.categories.items()],
        ),
        Heading(level=2, text="Per task"),
        Table(
            header=["task", "grader", *FIGURES, *REFACTORING_FIGURES],
            rows=[
                [
                    a.task_id + (" (golden fails: not counted)" if a.golden_fails else ""),
                    f"vacuous: {a.vacuous}" if a.vacuous else "-",
                    *_figures(a),
                ]
                for a in report.tasks
            ],
        ),
        Heading(level=2, text="Per operator"),
        Table(
            header=[
                "operator",
                "variants",
                "killed",
                "equivalent",
                "outside task",
                "holes",
                "explained",
                "passed",
                "brittle",
            ],
            rows=[
                [
                    name,
                    str(o.mutants + o.refactorings),
                    str(o.killed),
                    str(o.equivalent),
                    str(o.outside_task),
                    str(o.holes + o.survived),
                    str(o.explained),
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
    listed = (
        ("Holes", report.holes),
        ("Explained holes", report.explained),
        ("Outside the task", report.outside_task),
        ("Brittle", report.brittle),
        ("Equivalent", report.equivalent),
    )
    if any(findings for _, findings in listed):
        where = "" if link is not None else " (paths under the viewer of these runs: `scratchworld view RUN_DIR...`)"
        blocks.append(
            Paragraph(
                text=f"Each finding links to its job's page{where}: the golden and the variant side by side, every "
                "script, the change marked, with the verdict, the first observable difference and the run that "
                "showed it."
            )
        )
    for title, findings in listed:
        blocks += _finding_blocks(title, findings, href)
    return blocks


def render_audit(report: AuditReport, fmt: str, link: Callable[[Finding], str] | None = None) -> str:
    """The report in ``fmt``; ``link``: where a finding's page is from where the report is read (default: its
    ``page``, from the viewer's root)."""
    if fmt == "json":
        return report.model_dump_json(indent=2) + "\n"
    blocks = audit_blocks(report, link)
    return blocks_html(blocks) if fmt == "html" else blocks_markdown(blocks)
