"""The golden and a variant side by side (the audit job page's table): every script of both, the scripts that
differ and the changed block marked, and the projects' own text escaped."""

from __future__ import annotations

import re
from html import escape, unescape
from typing import Any

from scratchworld_dist.kinds.audit._programs import programs_html
from scratchworld_dist.kinds.audit.variants import enumerate_mutants, enumerate_refactorings, script_listings
from scratchworld_dist.sb3 import Project, block, circle_costume
from tests.support.audit_projects import mutation_project, refactoring_project


def marked(html: str) -> list[str]:
    return re.findall(r'<mark class="changed-block"[^>]*>(.*?)</mark>', html)


def opcode(project: dict[str, Any], target: str, block_id: str) -> str:
    return next(t for t in project["targets"] if t["name"] == target)["blocks"][block_id]["opcode"]


def test_every_script_of_both_programs_is_listed_and_the_change_marked() -> None:
    golden = mutation_project().to_project_json()
    mutant = next(
        m
        for m in enumerate_mutants(golden)
        if m.operator == "number_literal" and opcode(golden, m.target, m.block_id) == "operator_add"
    )
    html = programs_html(golden, mutant.project, (mutant.target, mutant.block_id), "mutant: number_literal")
    scripts = len(script_listings(golden))
    assert scripts == 5 and html.count('<span class="head">') == 2 * scripts  # the loose script too
    assert html.count('<tr class="script changed">') == 1 and "1 script(s) differ" in html
    # The changed block is a reporter inside a statement: the statement's line is marked, in both programs.
    old_line, new_line = marked(html)
    assert old_line.startswith("  data_changevariableby") and "operator_add" in old_line and old_line != new_line
    assert unescape(old_line) in mutant.before and unescape(new_line) in mutant.after  # the lines the row records


def test_a_deleted_statement_is_marked_where_it_was_and_a_new_script_against_nothing() -> None:
    golden = mutation_project().to_project_json()
    deleted = next(m for m in enumerate_mutants(golden) if m.operator == "delete_statement")
    html = programs_html(golden, deleted.project, (deleted.target, deleted.block_id), "mutant: delete_statement")
    assert len(marked(html)) == 1 and '<span class="line changed"><mark' in html  # only the golden has it
    project = refactoring_project().to_project_json()
    split = next(r for r in enumerate_refactorings(project) if r.operator == "split_at_broadcast")
    html = programs_html(project, split.project, (split.target, split.block_id), "refactoring: split_at_broadcast")
    # The script cut short, and the new one it broadcasts to, which the golden lacks.
    assert html.count("(not in this program)") == 1 and html.count('<tr class="script changed">') == 2


def test_the_projects_text_is_escaped_and_the_golden_alone_is_one_column() -> None:
    project = Project()
    hostile = project.sprite("<b>Cat</b>", costume=circle_costume("c", 5, "#000"))
    hostile.script(block("event_whenflagclicked"), block("looks_say", MESSAGE="</pre><script>alert(1)</script>"))
    golden = project.to_project_json()
    mutant = next(m for m in enumerate_mutants(golden) if m.operator == "text_literal")
    html = programs_html(golden, mutant.project, (mutant.target, mutant.block_id), "mutant: <i>text</i>")
    assert "<script>" not in html and "<b>" not in html and "<i>" not in html
    assert escape("Sprite: <b>Cat</b>") in html and escape("mutant: <i>text</i>") in html
    alone = programs_html(golden, None, None, "")
    assert "columns-1" in alone and "<th>golden</th></tr>" in alone and "changed" not in alone
