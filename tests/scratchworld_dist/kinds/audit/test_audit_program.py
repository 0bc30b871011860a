"""The audit's program model: read and written back equal, edits keeping links whole, the structure check, the form."""

from __future__ import annotations

import io
import json
import zipfile
from pathlib import Path

import pytest

from scratchworld_dist.kinds.audit.variants import Program, ProgramFormatError, program_form, structure_problems
from scratchworld_dist.kinds.audit.variants import _edits as edits
from tests.conftest import SUITE_DIR
from tests.support.audit_projects import mutation_project, refactoring_project, with_monitor
from tests.support.projects import counter_project, timing_project


def project_of(sb3: bytes) -> dict:
    with zipfile.ZipFile(io.BytesIO(sb3)) as archive:
        return json.loads(archive.read("project.json"))


def by_opcode(program: Program, target: str, opcode: str, nth: int = 0) -> str:
    return [b.id for b in program.target(target).all_blocks() if b.opcode == opcode][nth]


GOLDENS = sorted(SUITE_DIR.glob("*/*/*.sb3"))


@pytest.mark.parametrize("path", GOLDENS, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_our_task_projects_read_and_write_back_equal(path: Path) -> None:
    project = project_of(path.read_bytes())
    program = Program.parse(project)
    assert program.to_project() == project
    assert structure_problems(program) == []


@pytest.mark.upstream
def test_editor_saved_projects_read_and_write_back_equal(upstream_dir: Path) -> None:
    """Projects saved by the real editor: compact reporters loose on the workspace, numbers as JSON numbers,
    one-element fields, comments, block mutations. Written back key for key, in the same order."""
    files = sorted((upstream_dir / "scratch-gui" / "static").glob("*.sb3"))
    assert len(files) > 100
    for path in files:
        project = project_of(path.read_bytes())
        assert json.dumps(Program.parse(project).to_project()) == json.dumps(project), path.name


def test_writing_keeps_the_order_of_blocks_and_keys() -> None:
    project = project_of(timing_project())
    written = Program.parse(project).to_project()
    assert json.dumps(written) == json.dumps(project)


def test_a_copy_is_edited_alone() -> None:
    project = counter_project().to_project_json()
    program = Program.parse(project)
    copy = program.copy()
    say = by_opcode(copy, "Counter", "looks_say")
    edits.delete_statement(copy.target("Counter"), say)
    edits.rename(copy, "variable", "variable-Stage-count", "total")
    assert program.to_project() == project
    assert copy.to_project() != project
    assert project_of(counter_project().to_sb3()) == project  # parsing never touched the dict it read


def test_deleting_statements_closes_the_gap() -> None:
    program = Program.parse(mutation_project().to_project_json())
    cat = program.target("Cat")
    first_in_loop = by_opcode(program, "Cat", "data_changevariableby")
    loop = by_opcode(program, "Cat", "control_repeat")
    wait = by_opcode(program, "Cat", "control_wait")
    edits.delete_statement(cat, first_in_loop)
    assert cat.block(loop).inputs["SUBSTACK"].block_id == wait
    assert cat.block(wait).parent == loop
    assert first_in_loop not in cat.blocks
    assert not any(b.opcode == "operator_add" for b in cat.all_blocks())  # its reporter went with it
    edits.delete_statement(cat, wait)
    assert "SUBSTACK" not in cat.block(loop).inputs  # an empty substack is no input, as the builder writes it
    hat = cat.scripts()[0]
    edits.delete_statement(cat, cat.block(hat).next)
    assert cat.block(cat.block(hat).next).opcode == "data_setvariableto"
    assert structure_problems(program) == []


def test_swapping_and_unwrapping_keep_links_whole() -> None:
    program = Program.parse(mutation_project().to_project_json())
    cat = program.target("Cat")
    hat = cat.scripts()[0]
    first, second = cat.stack(hat)[1:3]
    edits.swap_with_next(cat, first)
    assert cat.stack(hat)[1:3] == [second, first]
    forever = by_opcode(program, "Cat", "control_forever")
    above = cat.block(forever).parent
    body = cat.stack(cat.block(forever).inputs["SUBSTACK"].block_id)
    edits.unwrap(cat, forever)
    assert cat.stack(hat)[-2:] == body
    assert cat.block(body[0]).parent == above
    assert forever not in cat.blocks
    assert structure_problems(program) == []


def test_unwrapping_a_c_block_in_the_middle_links_its_body_to_what_follows() -> None:
    program = Program.parse(mutation_project().to_project_json())
    cat = program.target("Cat")
    loop = by_opcode(program, "Cat", "control_repeat")
    above, below = cat.block(loop).parent, cat.block(loop).next
    body = cat.stack(cat.block(loop).inputs["SUBSTACK"].block_id)
    edits.unwrap(cat, loop)
    assert cat.block(above).next == body[0] and cat.block(body[0]).parent == above
    assert cat.block(body[-1]).next == below and cat.block(below).parent == body[-1]
    assert loop not in cat.blocks and structure_problems(program) == []


def test_dropping_a_reporter_lifts_its_operand() -> None:
    program = Program.parse(mutation_project().to_project_json())
    cat = program.target("Cat")
    negation = by_opcode(program, "Cat", "operator_not")
    both = by_opcode(program, "Cat", "operator_and")
    less = by_opcode(program, "Cat", "operator_lt")
    edits.lift_input(cat, negation, "OPERAND")
    assert cat.block(both).inputs["OPERAND2"].block_id == less
    assert cat.block(less).parent == both
    assert negation not in cat.blocks
    assert structure_problems(program) == []


def test_renaming_a_global_variable_follows_every_use() -> None:
    project = with_monitor(refactoring_project().to_project_json(), "points")
    program = Program.parse(project)
    edits.rename(program, "variable", "variable-Stage-points", "score")
    text = json.dumps(program.to_project())
    assert '"points"' not in text
    assert text.count('"score"') == json.dumps(project).count('"points"')
    assert program.to_project()["monitors"][0]["params"] == {"VARIABLE": "score"}


def test_renaming_a_local_variable_follows_readers_in_other_sprites() -> None:
    program = Program.parse(refactoring_project().to_project_json())
    edits.rename(program, "variable", "variable-Dog-steps", "paces")
    reader = program.target("Owl").block(by_opcode(program, "Owl", "sensing_of"))
    assert reader.fields["PROPERTY"].value == "paces"
    assert '"steps"' not in json.dumps(program.to_project())


def test_fresh_ids_are_unused_and_deterministic() -> None:
    program = Program.parse(counter_project().to_project_json())
    first = program.fresh_id("seed")
    assert first == program.fresh_id("seed") != program.fresh_id("other")
    edits.add_broadcast(program, "new", "seed")
    assert program.fresh_id("seed") not in (first, *program.stage.broadcasts)


@pytest.mark.parametrize(
    ("corrupt", "problem"),
    [
        (lambda b, ids: b[ids[1]].update(next="nowhere"), "next names the missing block 'nowhere'"),
        (lambda b, ids: b[ids[2]].update(parent=ids[0]), "whose parent is"),
        (lambda b, ids: b[ids[0]].update(parent=ids[1], topLevel=False), "is its own ancestor"),
        (lambda b, ids: b[ids[1]].update(topLevel=True), "is top-level but has the parent"),
        (lambda b, ids: b[ids[0]].pop("x"), "is top-level with no position"),
        (lambda b, ids: b[ids[1]]["fields"]["VARIABLE"].__setitem__(1, "ghost"), "uses the variable 'ghost'"),
    ],
)
def test_the_structure_check_finds_broken_links(corrupt, problem: str) -> None:
    project = counter_project().to_project_json()
    blocks = project["targets"][1]["blocks"]
    corrupt(blocks, list(blocks))
    problems = structure_problems(Program.parse(project))
    assert any(problem in p and p.startswith("Counter: ") for p in problems), problems


@pytest.mark.parametrize(
    ("mangle", "message"),
    [
        (lambda p: p.pop("targets"), "project.json has no list of targets"),
        (lambda p: p["targets"][1]["blocks"]["Counter-2"].pop("opcode"), "block 'Counter-2': not a block"),
        (lambda p: p["targets"][1]["blocks"]["Counter-2"].update(next=7), "next must be a block id or null"),
        (lambda p: p["targets"][1]["blocks"]["Counter-2"]["inputs"].update(VALUE=[9, 1]), "an input must be"),
        (lambda p: p["targets"][1]["blocks"]["Counter-2"]["fields"].update(VARIABLE="x"), "a field must be"),
        (lambda p: p["targets"][1].update(variables=[]), "variables is not an object"),
    ],
)
def test_unreadable_projects_get_a_one_line_error(mangle, message: str) -> None:
    project = counter_project().to_project_json()
    mangle(project)
    with pytest.raises(ProgramFormatError, match=message) as caught:
        Program.parse(project)
    assert "\n" not in str(caught.value)
    assert "Counter" in str(caught.value) or "targets" in str(caught.value)


def test_the_form_ignores_ids_and_places_but_sees_values_and_order() -> None:
    project = counter_project().to_project_json()
    form = program_form(Program.parse(project))
    moved = json.loads(json.dumps(project))
    top = next(b for b in moved["targets"][1]["blocks"].values() if b["topLevel"])
    top["x"] += 100
    assert program_form(Program.parse(moved)) == form
    renumbered = json.loads(json.dumps(project).replace("Counter-", "Renamed-"))
    assert program_form(Program.parse(renumbered)) == form
    changed = json.loads(json.dumps(project).replace('[4, "1"]', '[4, "2"]').replace('[4,"1"]', '[4,"2"]'))
    assert program_form(Program.parse(changed)) != form
    program = Program.parse(project_of(timing_project()))
    edits.move_to_end(program.target("Walker"), program.target("Walker").scripts()[0])
    assert program_form(program) != program_form(Program.parse(project_of(timing_project())))
