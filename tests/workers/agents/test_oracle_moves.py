"""The primitive oracle's harder gestures on hand-made projects: a block moving within its own script, a
C-block dropped where a block already hangs (Blockly would wrap it), scripts too far apart to show at once
(zoom-out), and an empty text input. Each time the gestures must leave what the composite API leaves from
the same trajectory."""

from __future__ import annotations

import pytest

from scratchworld_dist.sb3 import Block, Project, block, circle_costume
from tests.conftest import primitive_editor
from tests.support.primitive_oracle import composite_and_oracle, drive, sprite_blocks
from workers.agents._primitive_oracle import PrimitiveOracle
from workers.contract import CompositeAction
from workers.editor import EditorPool

pytestmark = pytest.mark.browser

SELECT_CAT = CompositeAction(api="select_sprite", args={"name": "Cat"})


def cat(*scripts: tuple[list[Block], int] | tuple[list[Block], int, int]) -> bytes:
    """A project whose sprite Cat has ``scripts``, each (blocks, y) at x 40, or (blocks, y, x)."""
    project = Project()
    sprite = project.sprite("Cat", costume=circle_costume("cat", 10, "#f80"))
    for blocks, y, *x in scripts:
        sprite.script(*blocks, x=x[0] if x else 40, y=y)
    return project.to_sb3()


async def index_of(pool: EditorPool, sb3: bytes) -> dict[str, int]:
    """The composite API's block index by opcode (each opcode once among Cat's blocks)."""
    async with primitive_editor(pool, sb3) as editor:
        return {opcode: index for opcode, (index, _) in (await sprite_blocks(editor, "Cat")).items()}


def connect(source: int, target: int, kind: str) -> CompositeAction:
    return CompositeAction(
        api="connect_blocks", args={"sourceBlockIndex": source, "targetBlockIndex": target, "placement": {"kind": kind}}
    )


async def test_a_block_moves_out_of_a_c_block_to_under_it_in_the_same_script(shared_pool: EditorPool) -> None:
    """Picked up, the say block leaves the repeat's mouth closed and the repeat's next connection higher up
    than a drag planned from inside the script would aim."""
    sb3 = cat(
        (
            [
                block("event_whenflagclicked"),
                block("control_repeat", TIMES=3, SUBSTACK=[block("looks_say", MESSAGE="hi")]),
                block("motion_movesteps", STEPS=10),
            ],
            40,
        )
    )
    at = await index_of(shared_pool, sb3)
    trajectory = [SELECT_CAT, connect(at["looks_say"], at["control_repeat"], "stack_after")]
    expected, performed, _ = await composite_and_oracle(shared_pool, sb3, trajectory)
    assert performed == expected
    assert "SUBSTACK" not in expected and "looks_say" in expected  # the mouth left empty, the say block under it


async def test_an_empty_c_block_dropped_where_a_block_hangs_keeps_it_under_not_inside(shared_pool: EditorPool) -> None:
    """Blockly wraps the block hanging under the say block in an empty repeat dropped there; the composite
    API puts it under the repeat. The oracle moves it aside first, then hangs it under the repeat."""
    sb3 = cat(
        ([block("event_whenflagclicked"), block("looks_say", MESSAGE="hi"), block("motion_movesteps", STEPS=10)], 40),
        ([block("control_repeat", TIMES=3)], 260),
    )
    at = await index_of(shared_pool, sb3)
    trajectory = [SELECT_CAT, connect(at["control_repeat"], at["looks_say"], "stack_after")]
    expected, performed, _ = await composite_and_oracle(shared_pool, sb3, trajectory)
    assert performed == expected
    assert "motion_movesteps" in expected


async def test_scripts_too_far_apart_to_show_at_once_are_joined_after_zooming_out(shared_pool: EditorPool) -> None:
    """The turn block sits 1,200 units under the script it joins: no wheel turn shows both, so the oracle
    clicks the workspace's zoom-out button until they fit."""
    sb3 = cat(
        ([block("event_whenflagclicked"), block("looks_say", MESSAGE="hi")], 40),
        ([block("motion_turnright", DEGREES=15)], 1240),
    )
    at = await index_of(shared_pool, sb3)
    trajectory = [SELECT_CAT, connect(at["motion_turnright"], at["looks_say"], "stack_after")]
    async with primitive_editor(shared_pool, sb3) as editor:
        before = (await editor.call("geometryLayout"))["scale"]  # type: ignore[index,call-overload]
        oracle = PrimitiveOracle(sb3, trajectory)
        await oracle.begin(editor)
        await drive(editor, oracle)
        after = (await editor.call("geometryLayout"))["scale"]  # type: ignore[index,call-overload]
        turn = await editor.call("geometryBlock", {"id": (await sprite_blocks(editor, "Cat"))["motion_turnright"][1]})
    assert after < before
    assert turn["attachment"]["input"] is None and turn["attachment"]["parent"]  # type: ignore[index,call-overload]


async def test_an_empty_text_input_is_typed_into(shared_pool: EditorPool) -> None:
    """An empty text input is drawn narrow; the oracle clicks its shadow to edit it."""
    sb3 = cat(([block("event_whenflagclicked"), block("looks_say", MESSAGE="")], 40))
    at = await index_of(shared_pool, sb3)
    value = CompositeAction(
        api="set_block_field", args={"blockIndex": at["looks_say"], "fieldName": "MESSAGE", "value": "hello"}
    )
    expected, performed, _ = await composite_and_oracle(shared_pool, sb3, [SELECT_CAT, value])
    assert performed == expected
    assert "hello" in expected


async def test_a_stack_taller_than_half_the_view_is_detached_after_zooming_out(shared_pool: EditorPool) -> None:
    """Fourteen wide say blocks fill a repeat's mouth, a second script beside it: no free spot in the view can
    take them, and a wheel turn by half a view would carry their grab point out of it, so the oracle zooms
    out until they fit (it used to turn the wheel and lose the block)."""
    says = [block("looks_say", MESSAGE=f"line {n} of a message long enough to make the block wide") for n in range(14)]
    sb3 = cat(
        ([block("event_whenflagclicked"), block("control_repeat", TIMES=3, SUBSTACK=says)], 40),
        ([block("event_whenflagclicked"), *(block("motion_movesteps", STEPS=n) for n in range(14))], 40, 700),
    )
    async with primitive_editor(shared_pool, sb3) as editor:
        found = await sprite_blocks(editor, "Cat")
        first = found["control_repeat"][0] + 2  # the first say, inside the mouth
    detach = CompositeAction(api="detach_blocks", args={"blockIndex": first})
    expected, performed, _ = await composite_and_oracle(shared_pool, sb3, [SELECT_CAT, detach])
    assert performed == expected
    assert expected.count("looks_say") == 14


async def test_an_angle_input_is_typed_into(shared_pool: EditorPool) -> None:
    """A direction input opens Scratch's dial as well as its text editor; the oracle types into the editor."""
    sb3 = cat(([block("event_whenflagclicked"), block("motion_pointindirection", DIRECTION=90)], 40))
    at = await index_of(shared_pool, sb3)
    field = {"blockIndex": at["motion_pointindirection"], "fieldName": "DIRECTION", "value": "45"}
    value = CompositeAction(api="set_block_field", args=field)
    expected, performed, _ = await composite_and_oracle(shared_pool, sb3, [SELECT_CAT, value])
    assert performed == expected
    assert '\\"NUM\\":\\"45\\"' in expected
