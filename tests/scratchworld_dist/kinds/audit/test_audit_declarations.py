"""A suite's declarations for the grader audit: per task, the answers its questions allow and the holes its
instruction leaves open (a reason and a matcher). Read from each task's ``audit.yaml`` in our layout, or from one
file for an upstream clone; a bad file fails in one line naming it; a hole is explained by the first entry whose
every key matches it."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from scratchworld_dist._errors import SuiteError
from scratchworld_dist.kinds.audit._declarations import (
    DEFAULT_UPSTREAM_FILE,
    HoleFacts,
    read_suite_declarations,
    read_task_declarations,
    suite_declarations,
)
from scratchworld_dist.kinds.audit._report import _explanation
from scratchworld_dist.kinds.audit._rows import AuditRow
from scratchworld_dist.suites import load_suite
from tests.support.small_suites import native_suite, upstream_clone

QUESTION_WORDING = """\
answers: numbers
explained:
  - reason: the instruction asks for a question, not its wording
    match: {block: sensing_askandwait, input: QUESTION, difference: bubble}
  - reason: a speed the instruction leaves free
    match: {operator: number_literal, target: Ball, variable: speed}
"""

ASKED = HoleFacts(
    operator="text_literal", target="Calculator", block_id="Calculator-2", block_opcode="sensing_askandwait",
    change="QUESTION: 'Enter the first number' -> 'ENTER THE FIRST NUMBER'", difference="bubble",
)  # fmt: skip


def test_a_hole_is_explained_by_the_first_entry_whose_every_key_matches(tmp_path: Path) -> None:
    path = tmp_path / "audit.yaml"
    path.write_text(QUESTION_WORDING)
    declared = read_task_declarations(path)
    assert declared.answers == "numbers" and declared.source == str(path)
    entry = declared.explanation(ASKED)
    assert entry is not None and entry.reason.startswith("the instruction asks for a question")
    assert ASKED.input == "QUESTION"
    # Each key must match: another block, another input, another trace field, and the first entry fails.
    for changed in ({"block_opcode": "looks_say"}, {"change": "MESSAGE: 'a' -> 'b'"}, {"difference": "x"}):
        assert declared.explanation(ASKED.model_copy(update=changed)) is None, changed
    # The block matches by id as well; a variable's difference by its name; `var` is any variable's field.
    assert declared.explanation(ASKED.model_copy(update={"block_opcode": "", "block_id": "Calculator-2"})) is None
    speed = HoleFacts(
        operator="number_literal", target="Ball", block_id="b", difference="var:v1.value", variable="speed"
    )
    assert declared.explanation(speed) is not None
    assert declared.explanation(speed.model_copy(update={"variable": "score"})) is None
    by_id = read_task_declarations(
        _write(tmp_path / "id.yaml", "explained: [{reason: r, match: {block: b, difference: var}}]")
    )
    assert by_id.explanation(speed) is not None


def _write(path: Path, text: str) -> Path:
    path.write_text(text)
    return path


@pytest.mark.parametrize(
    ("text", "says"),
    [
        ("answers: [numbers", "not YAML (line"),
        ("- a list", "must be a mapping"),
        ("answer: numbers", "answer: Extra inputs are not permitted"),
        ("answers: digits", "answers: Input should be 'any', 'text', 'numbers', 'integers' or 'words'"),
        ("explained: [{reason: r, match: {}}]", "a matcher needs at least one of operator, target, block"),
        (
            "explained: [{reason: r, match: {operator: flip}}]",
            "unknown operator 'flip' (operators: arithmetic_operator",
        ),
        ("explained: [{reason: '', match: {block: b}}]", "explained.0.reason: String should have at least 1 character"),
        ("explained: [{match: {block: b}}]", "explained.0.reason: Field required"),
        ("explained: [{reason: r, match: {block: b, opcode: x}}]", "explained.0.match.opcode: Extra inputs"),
    ],
)
def test_a_bad_declarations_file_fails_in_one_line_naming_it(text: str, says: str, tmp_path: Path) -> None:
    path = _write(tmp_path / "audit.yaml", text)
    with pytest.raises(SuiteError) as caught:
        read_task_declarations(path)
    message = str(caught.value)
    assert message.startswith(f"{path}: ") and says in message and "\n" not in message, message


def test_our_layout_reads_each_tasks_file_and_an_upstream_clone_one_file(tmp_path: Path) -> None:
    task = native_suite(tmp_path / "ours")
    assert suite_declarations(load_suite(tmp_path / "ours")) == {}  # no file: nothing declared
    _write(task / "audit.yaml", QUESTION_WORDING)
    (declared,) = suite_declarations(load_suite(tmp_path / "ours")).values()
    assert declared.answers == "numbers" and declared.source.endswith("sum_two_numbers/audit.yaml")
    _write(task / "audit.yaml", "explained: [{reason: r, match: {operater: x}}]")
    with pytest.raises(SuiteError, match=r"audit\.yaml: bad audit declarations: explained\.0\.match\.operater"):
        suite_declarations(load_suite(tmp_path / "ours"))

    clone = load_suite(upstream_clone(tmp_path / "ScratchWorld"))
    beside = _write(tmp_path / "upstream-audit.yaml", "tasks:\n  calc:\n    answers: integers\n")
    assert suite_declarations(clone, beside)["calc"].answers == "integers"
    assert "(tasks.calc)" in suite_declarations(clone, beside)["calc"].source
    _write(beside, "tasks:\n  calk:\n    answers: integers\n")  # a typo is no silent no-op
    with pytest.raises(SuiteError, match=r"tasks.calk: the suite has no such task"):
        suite_declarations(clone, beside)
    assert read_suite_declarations(beside)["calk"].answers == "integers"  # (the shipped file spans every task)
    assert suite_declarations(clone) == read_suite_declarations(DEFAULT_UPSTREAM_FILE)  # a clone's default: valid


def test_an_audit_row_is_explained_only_as_a_hole_and_with_where_it_is_declared(tmp_path: Path) -> None:
    path = _write(tmp_path / "audit.yaml", QUESTION_WORDING)
    declarations = {"sum_two_numbers": read_task_declarations(path)}
    row = AuditRow(
        job_id="j", attempt=1, task_id="sum_two_numbers", variant="mutant", operator="text_literal",
        variant_id="v", target="Calculator", block_id="Calculator-2", description="d", before="", after="",
        tests_passed=3, tests_total=3, failing_tests="[]", verdict="hole", observed="differs",
        change=ASKED.change, block_opcode="sensing_askandwait",
        first_difference=json.dumps({"frame": 1, "target": "Calculator", "field": "bubble", "a": None, "b": None}),
    )  # fmt: skip
    explained = _explanation(row, declarations)
    assert explained is not None and explained.startswith("the instruction asks") and str(path) in explained
    assert _explanation(row.model_copy(update={"verdict": "equivalent"}), declarations) is None
    assert _explanation(row.model_copy(update={"task_id": "other"}), declarations) is None
    moved = row.model_copy(update={"first_difference": json.dumps({"field": "x"})})
    assert _explanation(moved, declarations) is None  # the difference is elsewhere: no explanation
