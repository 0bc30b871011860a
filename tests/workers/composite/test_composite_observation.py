"""Composite mode in a real editor: the observation text in the benchmark's format, indices, targets,
variables and lists in scope, and the pseudocode of what a saved project runs."""

from __future__ import annotations

import re

import pytest

from tests.conftest import SUITE_DIR
from tests.workers.composite.conftest import BASE_CAT, code, fails, ok
from workers import composite
from workers.contract import EvaluationSpec
from workers.editor import Editor
from workers.evaluation import Evaluator

pytestmark = pytest.mark.browser


async def test_the_observation_has_every_section_in_the_benchmark_format(cat: Editor) -> None:
    observation = await composite.observe(cat)
    assert observation.text == (
        "## Current Editing Target\nCat\n\n"
        "## Target Variables In Scope\nname: score, scope: all\n\n"
        "## Target Lists In Scope\nNone\n\n"
        "## All Available Targets\nStage, Cat, Dog\n\n"
        "## Blocks Pseudocode\n" + BASE_CAT
    )
    assert observation.editing_target == "Cat"
    assert observation.block_count == 6
    assert [(t.name, t.is_stage) for t in observation.targets] == [("Stage", True), ("Cat", False), ("Dog", False)]


async def test_indices_are_deterministic_and_survive_save_and_reload(cat: Editor) -> None:
    await ok(cat, "add_block", blockType="operator_add")
    first = (await composite.observe(cat)).text
    assert (await composite.observe(cat)).text == first
    saved = await cat.save_project()
    await cat.load_project(saved)
    await ok(cat, "select_sprite", name="cat")  # case-insensitive
    assert (await composite.observe(cat)).text == first


async def test_select_sprite_and_stage(cat: Editor) -> None:
    assert await ok(cat, "select_stage") == {"editingTarget": "Stage"}
    assert (await composite.observe(cat)).editing_target == "Stage"
    message = await fails(cat, "select_sprite", "NOT_FOUND", name="Bird")
    assert '"Cat"' in message
    assert '"Dog"' in message
    await fails(cat, "select_sprite", "INVALID_ARG", name="")
    await fails(cat, "select_sprite", "INVALID_ARG", name=7)


async def test_variables_and_lists_by_scope(cat: Editor) -> None:
    created = (await ok(cat, "add_variable", name="lives", scope="sprite"))["created"]
    assert (created["scope"], created["created"]) == ("sprite", True)
    again = (await ok(cat, "add_variable", name="lives", scope="sprite"))["created"]
    assert (again["id"], again["created"]) == (created["id"], False)  # reused, not duplicated
    await ok(cat, "add_list", name="names", scope="all")
    await fails(cat, "add_variable", "INVALID_ARG", name="x", scope="world")
    text = (await composite.observe(cat)).text
    assert "## Target Variables In Scope\nname: lives, scope: sprite; name: score, scope: all\n" in text
    assert "## Target Lists In Scope\nname: names, scope: all\n" in text
    await ok(cat, "select_stage")
    await fails(cat, "add_variable", "INVALID_ARG", name="local", scope="sprite")
    assert "lives" not in (await composite.observe(cat)).text  # Cat's own variable is not the stage's


async def test_the_saved_project_runs_what_the_pseudocode_shows(cat: Editor, evaluator: Evaluator) -> None:
    await ok(cat, "select_sprite", name="Dog")
    await ok(cat, "add_variable", name="n", scope="sprite")
    hat = (await ok(cat, "add_block", blockType="event_whenflagclicked"))["index"]
    setter = (await ok(cat, "add_block", blockType="data_setvariableto", creation={"variableName": "n"}))["index"]
    await ok(cat, "connect_blocks", sourceBlockIndex=setter, targetBlockIndex=hat, placement={"kind": "stack_after"})
    await ok(cat, "set_block_field", blockIndex=2, fieldName="VALUE", value=3)
    repeat = (await ok(cat, "add_block", blockType="control_repeat"))["index"]
    await ok(cat, "connect_blocks", sourceBlockIndex=repeat, targetBlockIndex=2, placement={"kind": "stack_after"})
    await ok(cat, "set_block_field", blockIndex=3, fieldName="TIMES", value=4)
    change = (await ok(cat, "add_block", blockType="data_changevariableby", creation={"variableName": "n"}))["index"]
    await ok(
        cat,
        "connect_blocks",
        sourceBlockIndex=change,
        targetBlockIndex=3,
        placement={"kind": "statement_into", "inputName": "SUBSTACK"},
    )
    await ok(cat, "set_block_field", blockIndex=4, fieldName="VALUE", value=2.5)
    assert await code(cat) == (
        "#1 [top] event_whenflagclicked\n"
        '#2 data_setvariableto\n- field VARIABLE: "n" {choices: {"variableOptions":["n","score"]}}\n'
        '- input VALUE: "3" (text)\n'
        "#3 control_repeat\n- input TIMES: 4 (math_whole_number)\n- SUBSTACK:\n"
        '  #4 data_changevariableby\n  - field VARIABLE: "n" {choices: {"variableOptions":["n","score"]}}\n'
        "  - input VALUE: 2.5 (math_number)"
    )
    script = """module.exports = async (vm) => {
      vm.greenFlag();
      const dog = vm.runtime.targets.find((t) => t.getName() === 'Dog');
      const n = () => Object.values(dog.variables).find((v) => v.name === 'n').value;
      for (let i = 0; i < 200 && n() != 13; i++) await new Promise((r) => setTimeout(r, 10));
      return {passed: n() == 13 ? 1 : 0, total: 1, details: [{name: 'n ends at 3 + 4 x 2.5', passed: n() == 13}]};
    };"""
    spec = EvaluationSpec(script_name="runs.js", script_source=script, timeout_s=20)
    result = await evaluator.evaluate(await cat.save_project(), spec)
    assert result.error is None, result.error
    assert result.success


MAZE_BALL_TAIL = """#16 [top] event_whenflagclicked
#17 control_forever
- SUBSTACK:
  #18 control_if
  - input CONDITION:
    #19 sensing_touchingcolor
    - input COLOR: "#1505ff" (colour_picker)
  - SUBSTACK:
    #20 motion_movesteps
    - input STEPS: -10 (math_number)"""

MAZE_GOAL = """#1 [top] event_whenflagclicked
#2 control_forever
- SUBSTACK:
  #3 control_if
  - input CONDITION:
    #4 sensing_touchingobject
    - input TOUCHINGOBJECTMENU: "Ball" (sensing_touchingobjectmenu) \
{choices: {"touchingobjectmenuOptions":["mouse-pointer","edge","Ball"]}}
  - SUBSTACK:
    #5 looks_say
    - input MESSAGE: "You win!" (text)"""


@pytest.mark.upstream
async def test_pseudocode_of_the_upstream_maze_starter(editor: Editor, upstream_dir) -> None:
    await editor.load_project((upstream_dir / "scratch-gui" / "static" / "maze_starter.sb3").read_bytes())
    await ok(editor, "select_sprite", name="Ball")
    ball = await code(editor)
    assert ball.startswith(
        "#1 [top] event_whenflagclicked\n#2 motion_gotoxy\n"
        "- input X: -205 (math_number)\n- input Y: 147 (math_number)\n"
        "#3 motion_pointindirection\n- input DIRECTION: 90 (math_angle)\n\n#4 [top] event_whenkeypressed\n"
        '- field KEY_OPTION: "up arrow" {choices: {"keyoptionOptions":["space","up arrow",'
    )
    assert ball.endswith(MAZE_BALL_TAIL)
    assert ball.count("[top] event_whenkeypressed") == 4
    await ok(editor, "select_sprite", name="Goal")
    assert await code(editor) == MAZE_GOAL


@pytest.mark.upstream
@pytest.mark.slow
async def test_every_upstream_starter_can_be_observed_in_every_target(editor: Editor, upstream_dir) -> None:
    static = upstream_dir / "scratch-gui" / "static"
    starters = sorted(p for p in static.glob("*.sb3") if "golden" not in p.name)[::12]  # a spread of ~17 projects
    assert len(starters) >= 10
    for path in starters:
        await editor.load_project(path.read_bytes())
        observation = await composite.observe(editor)
        for target in observation.targets:
            await ok(editor, "select_stage") if target.is_stage else await ok(editor, "select_sprite", name=target.name)
            indices = [int(match) for match in re.findall(r"^ *#(\d+) ", await code(editor), flags=re.MULTILINE)]
            assert indices == list(range(1, len(indices) + 1)), path.name


def test_every_task_of_our_suite_has_a_golden_trajectory() -> None:
    assert sorted(p.parent.name for p in SUITE_DIR.glob("*/*/task.json")) == sorted(
        p.parent.name for p in SUITE_DIR.glob("*/*/golden_trajectory.json")
    )
