"""An audit job on the viewer's job page: the first observable difference from the golden, the grader's verdict,
and the golden and the variant side by side (every script, the change marked), which the report's findings link to.
"""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from html import escape
from pathlib import Path

from pydantic import BaseModel

from scratchworld_dist.kinds.audit._programs import programs_html
from scratchworld_dist.kinds.audit._remake import ProgramsUnavailableError, remade_programs
from scratchworld_dist.kinds.audit._rows import AuditRow
from scratchworld_dist.viewer import AttemptPanel
from workers.kinds.audit import ShownBy

GOOD = {"killed", "passed", "golden_passes"}
"""Verdicts of a grader that judged right (a green badge); a hole, a brittle test or a failing golden are red,
an equivalent mutant (no test could kill it) grey."""

WRONG = {"hole", "survived", "brittle", "golden_fails"}

VACUOUS = {
    "never_starts": "its tests never start the program (no green flag, no script started): they pass any program",
    "observes_nothing": "its tests read nothing the program changes: they pass any program",
}

MEANING = {
    "killed": "a test failed this mutant, as a sound grader should",
    "equivalent": "every test passed this mutant, and it behaves as the golden does: no test could tell them apart",
    "hole": "a grader hole: every test passed this mutant, which behaves otherwise than the golden in a run the task"
    " allows (unless the suite declares the difference open: an explained hole, see the report)",
    "outside_task": "every test passed this mutant, which behaves otherwise than the golden only under answers the "
    "task's instruction rules out: outside the task, not a hole",
    "survived": "every test passed this mutant, and it could not be traced to tell whether it behaves as the golden",
    "passed": "every test passed this refactoring, as a sound grader should",
    "brittle": "a brittle grader: a test failed this refactoring, which was written to behave as the golden does",
    "golden_passes": "the golden passes its own tests, so its variants' verdicts measure the grader",
    "golden_fails": "the golden fails its own tests: its variants' verdicts measure nothing",
    "error": "no verdict: the evaluation itself failed",
}


def variant_panel(rows: Mapping[str, Sequence[BaseModel]], run_dir: Path) -> AttemptPanel | None:
    row = next((r for r in rows.get("audits", ()) if isinstance(r, AuditRow)), None)
    if row is None:
        return None
    body = _evidence(row) + _verdict(row) + _programs(row, run_dir)
    return AttemptPanel(title="Golden" if row.variant == "golden" else "Variant", html=body, shows_project=False)


def _evidence(row: AuditRow) -> str:
    """The first observable difference, first: what the tests let through (or that there is none)."""
    if row.evidence:
        shown = ShownBy.model_validate_json(row.shown_by).describe() if row.shown_by else None
        return (
            '<p class="audit-evidence"><strong>First observable difference from the golden:</strong> '
            f"<code>{escape(row.evidence)}</code></p>\n"
            + (f'<p class="audit-shown-by">Shown by {escape(shown)}.</p>\n' if shown else "")
        )
    if row.observed == "equivalent":
        runs = f"all {row.runs_compared} runs" if row.runs_compared else "both traces"
        return (
            f"<p class=\"audit-evidence\">Observably the same as the golden: {runs} (the tests' own, the task's "
            "exploration) agree frame by frame.</p>\n"
        )
    if row.vacuous:
        return (
            f'<p class="audit-evidence warning">Vacuous grader: {escape(VACUOUS.get(row.vacuous, row.vacuous))}.</p>\n'
        )
    return ""


def _verdict(row: AuditRow) -> str:
    badge = "passed" if row.verdict in GOOD else "failed" if row.verdict in WRONG else row.verdict
    failing = ", ".join(escape(name) for name in json.loads(row.failing_tests)) or "none"
    change = (
        "the golden project, unchanged"
        if row.variant == "golden"
        else f"{escape(row.variant)} {escape(row.operator)} at {escape(row.target)} / {escape(row.block_id)}: "
        f"{escape(row.description)}"
    )
    return (
        '<table class="kv audit">\n'
        f"<tr><th>change</th><td>{change}</td></tr>\n"
        f'<tr><th>verdict</th><td><span class="badge {badge}">{escape(row.verdict)}</span> '
        f"{escape(MEANING.get(row.verdict, ''))}</td></tr>\n"
        f"<tr><th>tests</th><td>{row.tests_passed} of {row.tests_total} passed; failing: {failing}"
        f"{_stop(row)}</td></tr>\n"
        "</table>\n"
    )


def _stop(row: AuditRow) -> str:
    """That a killed mutant's tests stopped at the one that killed it, and how many did not run."""
    if row.stopped_at is None:
        return ""
    return f" (its tests stopped at {escape(row.stopped_at)}: {row.tests_not_run} after it not run)"


def _programs(row: AuditRow, run_dir: Path) -> str:
    """Both programs in full, or (when they cannot be made again) the changed scripts the row recorded."""
    try:
        programs = remade_programs(run_dir, row.task_id, row.job_id)
    except ProgramsUnavailableError as exc:
        note = f'<p class="warning">Programs not shown: {escape(str(exc))}</p>\n'
        if row.variant == "golden":
            return note
        return (
            f'{note}<table class="kv audit">\n'
            f'<tr><th>before</th><td><pre class="listing">{escape(row.before)}</pre></td></tr>\n'
            f'<tr><th>after</th><td><pre class="listing">{escape(row.after)}</pre></td></tr>\n'
            "</table>"
        )
    if programs.variant is None:
        return "<h4>The golden</h4>\n" + programs_html(programs.golden, None, None, "")
    label = f"{row.variant}: {row.operator}"
    table = programs_html(programs.golden, programs.variant, (row.target, row.block_id), label)
    return "<h4>The golden and the variant</h4>\n" + table
