"""The primitive oracle's harder gestures on hand-made projects: a block moving within its own script, a
C-block dropped where a block already hangs (Blockly would wrap it), scripts too far apart to show at once
(zoom-out), and an empty text input. Each time the gestures must leave what the composite API leaves from
the same trajectory."""

from __future__ import annotations

import pytest

from scratchworld_dist.sb3 import Block, Project, block, circle_costume, variable
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


async def set_field(pool: EditorPool, sb3: bytes, opcode: str, field: str, value: str) -> tuple[str, str]:
    """What setting ``field`` of Cat's ``opcode`` block to ``value`` leaves: through the composite API, and
    through the oracle's gestures."""
    at = await index_of(pool, sb3)
    args = {"blockIndex": at[opcode], "fieldName": field, "value": value}
    expected, performed, _ = await composite_and_oracle(
        pool, sb3, [SELECT_CAT, CompositeAction(api="set_block_field", args=args)]
    )
    return expected, performed


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
    expected, performed = await set_field(shared_pool, sb3, "looks_say", "MESSAGE", "hello")
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
    expected, performed = await set_field(shared_pool, sb3, "motion_pointindirection", "DIRECTION", "45")
    assert performed == expected
    assert '\\"NUM\\":\\"45\\"' in expected


async def test_a_colour_the_stage_shows_only_in_small_shapes_is_picked_with_the_eyedropper(
    shared_pool: EditorPool,
) -> None:
    """No slider setting gives #fff700, and the small stage draws the sprite wearing it three pixels wide,
    edges blended: the eyedropper is aimed at the one pixel of exactly that colour (it used to want 5 x 5)."""
    project = Project()
    sprite = project.sprite("Cat", costume=circle_costume("cat", 3, "#fff700"))
    touching = block("sensing_touchingcolor", COLOR="#0000ff")
    sprite.script(block("event_whenflagclicked"), block("control_wait_until", CONDITION=touching))
    expected, performed = await set_field(shared_pool, project.to_sb3(), "sensing_touchingcolor", "COLOR", "#fff700")
    assert performed == expected
    assert "#fff700" in expected


def script_at_the_bottom_of_the_view() -> bytes:
    """decimal_to_binary's workspace at step 30, rebuilt: its script ends at the view's bottom edge, with an
    empty mod block in a join and loose reporters above it. Every straight way into the mod block's first
    input from where there is room crosses other inputs, and below the script there is no room in view."""
    project = Project()
    sprite = project.sprite("Cat", costume=circle_costume("cat", 10, "#f80"))
    for name in ("number", "binary"):
        project.stage.variable(name, 0)
    mod = block("operator_mod", NUM1="", NUM2="")
    sprite.script(
        block("event_whenflagclicked"),
        block("sensing_askandwait", QUESTION="Input"),
        block("data_setvariableto", VARIABLE="number", VALUE=block("sensing_answer")),
        block("data_setvariableto", VARIABLE="binary", VALUE="0"),
        block(
            "control_repeat_until",
            CONDITION=block("operator_equals", OPERAND1=variable("number"), OPERAND2="50"),
            SUBSTACK=[
                block(
                    "data_setvariableto", VARIABLE="binary", VALUE=block("operator_join", STRING1=mod, STRING2="banana")
                )
            ],
        ),
        block("looks_say", MESSAGE=variable("binary")),
        x=520,
        y=480,
    )
    sprite.script(block("data_setvariableto", VARIABLE="number", VALUE="0"), x=180, y=230)
    sprite.script(variable("number"), x=530, y=60)
    return project.to_sb3()


async def test_a_value_with_no_way_in_from_the_view_goes_in_after_zooming_out(shared_pool: EditorPool) -> None:
    """No free spot in view offers a path that lands (it used to diverge here); one zoom-out shows room under
    the script, from where the reporter goes straight up into the input."""
    sb3 = script_at_the_bottom_of_the_view()
    async with primitive_editor(shared_pool, sb3) as editor:
        mod = (await sprite_blocks(editor, "Cat"))["operator_mod"][0]
        reporter = -1  # the loose variable reporter's index
        order = (await editor.call("compositeBlockIds"))["ids"]  # type: ignore[index,call-overload]
        for index, block_id in enumerate(order):
            info = await editor.call("geometryBlock", {"id": block_id}) if block_id else None
            if info and info["opcode"] == "data_variable" and info["attachment"] is None:  # type: ignore[index,call-overload]
                reporter = index
    assert reporter > 0
    placement = {"kind": "value_into", "inputName": "NUM1"}
    into_mod = {"sourceBlockIndex": reporter, "targetBlockIndex": mod, "placement": placement}
    trajectory = [SELECT_CAT, CompositeAction(api="connect_blocks", args=into_mod)]
    expected, performed, _ = await composite_and_oracle(shared_pool, sb3, trajectory)
    assert performed == expected
