"""Composite mode in a real editor: every editing API, where it places blocks, and its errors (hostile
requests included)."""

from __future__ import annotations

import pytest

from tests.workers.composite.conftest import BASE_CAT, code, fails, ok
from workers import composite
from workers.editor import Editor

pytestmark = pytest.mark.browser


async def test_add_block_reports_its_index_and_refuses_what_it_cannot_make(cat: Editor) -> None:
    data = await ok(cat, "add_block", blockType="motion_setrotationstyle")
    assert (data["index"], data["opcode"]) == (7, "motion_setrotationstyle")
    assert (await code(cat)).endswith(
        '#7 [top] motion_setrotationstyle\n- field STYLE: "left-right" '
        '{choices: {"styleOptions":["left-right","don\'t rotate","all around"]}}'
    )
    await fails(cat, "add_block", "INVALID_ARG", blockType="motion_teleport")  # never a silent success
    await fails(cat, "add_block", "INVALID_ARG", blockType="pen_clear")  # outside the catalog
    await fails(cat, "add_block", "INVALID_ARG", blockType="data_variable")  # needs creation.variableName
    await fails(cat, "add_block", "NOT_FOUND", blockType="data_variable", creation={"variableName": "nope"})
    await fails(cat, "add_block", "NOT_FOUND", blockType="data_addtolist")  # no list exists yet
    reporter = await ok(cat, "add_block", blockType="data_variable", creation={"variableName": "score"})
    assert reporter["variable"] == "score"
    await ok(cat, "select_stage")
    await fails(cat, "add_block", "UNSUPPORTED", blockType="motion_movesteps")


async def test_stack_after_moves_one_block_and_heals_the_gap(cat: Editor) -> None:
    # Move "turn" (#3) after "say" (#4): move, say, turn.
    await ok(cat, "connect_blocks", sourceBlockIndex=3, targetBlockIndex=4, placement={"kind": "stack_after"})
    assert (await code(cat)).startswith(
        "#1 [top] event_whenflagclicked\n#2 motion_movesteps\n- input STEPS: 10 (math_number)\n"
        '#3 looks_say\n- input MESSAGE: "hi" (text)\n#4 motion_turnright\n'
    )
    # Move "move" (#2) into the middle of the forever loop's stack: after changexby.
    await ok(cat, "connect_blocks", sourceBlockIndex=2, targetBlockIndex=6, placement={"kind": "stack_after"})
    assert await code(cat) == (
        "#1 [top] event_whenflagclicked\n"
        '#2 looks_say\n- input MESSAGE: "hi" (text)\n'
        "#3 motion_turnright\n- input DEGREES: 15 (math_number)\n\n"
        "#4 [top] control_forever\n- SUBSTACK:\n"
        "  #5 motion_changexby\n  - input DX: 1 (math_number)\n"
        "  #6 motion_movesteps\n  - input STEPS: 10 (math_number)"
    )


async def test_stack_before_takes_the_first_place_in_a_c_slot(cat: Editor) -> None:
    await ok(cat, "connect_blocks", sourceBlockIndex=4, targetBlockIndex=6, placement={"kind": "stack_before"})
    assert (await code(cat)).endswith(
        "#4 [top] control_forever\n- SUBSTACK:\n"
        '  #5 looks_say\n  - input MESSAGE: "hi" (text)\n'
        "  #6 motion_changexby\n  - input DX: 1 (math_number)"
    )


async def test_a_hat_goes_on_top_of_a_script_with_its_whole_stack(cat: Editor) -> None:
    hat = (await ok(cat, "add_block", blockType="event_whenthisspriteclicked"))["index"]
    await ok(cat, "connect_blocks", sourceBlockIndex=hat, targetBlockIndex=5, placement={"kind": "stack_before"})
    assert (await code(cat)).endswith(
        "#5 [top] event_whenthisspriteclicked\n#6 control_forever\n- SUBSTACK:\n"
        "  #7 motion_changexby\n  - input DX: 1 (math_number)"
    )
    message = await fails(
        cat,
        "connect_blocks",
        "CONNECTION_MISMATCH",
        sourceBlockIndex=5,
        targetBlockIndex=2,
        placement={"kind": "stack_before"},
    )
    assert "hat" in message
    await fails(
        cat,
        "connect_blocks",
        "CONNECTION_MISMATCH",
        sourceBlockIndex=5,
        targetBlockIndex=2,
        placement={"kind": "stack_after"},
    )


async def test_statement_into_chains_the_old_content_after_the_new(cat: Editor) -> None:
    await ok(
        cat,
        "connect_blocks",
        sourceBlockIndex=2,
        targetBlockIndex=5,
        placement={"kind": "statement_into", "inputName": "SUBSTACK"},
    )
    assert (await code(cat)).endswith(
        "#4 [top] control_forever\n- SUBSTACK:\n"
        "  #5 motion_movesteps\n  - input STEPS: 10 (math_number)\n"
        "  #6 motion_changexby\n  - input DX: 1 (math_number)"
    )
    message = await fails(
        cat,
        "connect_blocks",
        "INPUT_NOT_FOUND",
        sourceBlockIndex=2,
        targetBlockIndex=4,
        placement={"kind": "statement_into", "inputName": "SUBSTACK2"},
    )
    assert "SUBSTACK" in message
    await fails(
        cat,
        "connect_blocks",
        "INPUT_NOT_FOUND",
        sourceBlockIndex=2,
        targetBlockIndex=3,
        placement={"kind": "statement_into", "inputName": "SUBSTACK"},
    )


async def test_value_into_covers_the_literal_and_unplugs_an_old_reporter(cat: Editor) -> None:
    first = (await ok(cat, "add_block", blockType="motion_xposition"))["index"]
    await ok(
        cat,
        "connect_blocks",
        sourceBlockIndex=first,
        targetBlockIndex=2,
        placement={"kind": "value_into", "inputName": "STEPS"},
    )
    assert "#2 motion_movesteps\n- input STEPS:\n  #3 motion_xposition\n#4 motion_turnright" in await code(cat)
    second = (await ok(cat, "add_block", blockType="operator_random"))["index"]
    data = await ok(
        cat,
        "connect_blocks",
        sourceBlockIndex=second,
        targetBlockIndex=2,
        placement={"kind": "value_into", "inputName": "STEPS"},
    )
    assert data["detachedBlockId"]
    text = await code(cat)
    assert (
        "- input STEPS:\n  #3 operator_random\n  - input FROM: 1 (math_number)\n  - input TO: 10 (math_number)" in text
    )
    assert text.endswith("[top] motion_xposition")  # the old reporter is a script of its own now
    # Detaching the reporter brings the literal back.
    await ok(cat, "detach_blocks", blockIndex=3)
    assert "#2 motion_movesteps\n- input STEPS: 10 (math_number)\n" in await code(cat)


async def test_value_into_checks_shapes_and_inputs(cat: Editor) -> None:
    boolean = (await ok(cat, "add_block", blockType="sensing_mousedown"))["index"]
    round_ = (await ok(cat, "add_block", blockType="motion_direction"))["index"]
    iff = (await ok(cat, "add_block", blockType="control_if"))["index"]
    message = await fails(
        cat,
        "connect_blocks",
        "CONNECTION_MISMATCH",
        sourceBlockIndex=round_,
        targetBlockIndex=iff,
        placement={"kind": "value_into", "inputName": "CONDITION"},
    )
    assert "boolean" in message
    await ok(
        cat,
        "connect_blocks",
        sourceBlockIndex=boolean,
        targetBlockIndex=iff,
        placement={"kind": "value_into", "inputName": "CONDITION"},
    )
    message = await fails(
        cat,
        "connect_blocks",
        "INPUT_NOT_FOUND",
        sourceBlockIndex=round_ - 1,
        targetBlockIndex=2,
        placement={"kind": "value_into", "inputName": "STEP"},
    )
    assert "STEPS" in message
    await fails(
        cat,
        "connect_blocks",
        "CONNECTION_MISMATCH",
        sourceBlockIndex=3,
        targetBlockIndex=2,
        placement={"kind": "value_into", "inputName": "STEPS"},
    )
    await fails(
        cat,
        "connect_blocks",
        "CONNECTION_MISMATCH",
        sourceBlockIndex=round_ - 1,
        targetBlockIndex=2,
        placement={"kind": "stack_after"},
    )


async def test_wrap_puts_the_rest_of_a_stack_inside_a_c_block(cat: Editor) -> None:
    repeat = (await ok(cat, "add_block", blockType="control_repeat"))["index"]
    await ok(cat, "connect_blocks", sourceBlockIndex=repeat, targetBlockIndex=3, placement={"kind": "wrap"})
    assert (await code(cat)).startswith(
        "#1 [top] event_whenflagclicked\n#2 motion_movesteps\n- input STEPS: 10 (math_number)\n"
        "#3 control_repeat\n- input TIMES: 10 (math_whole_number)\n- SUBSTACK:\n"
        "  #4 motion_turnright\n  - input DEGREES: 15 (math_number)\n"
        '  #5 looks_say\n  - input MESSAGE: "hi" (text)\n'
    )
    await fails(
        cat, "connect_blocks", "CONNECTION_MISMATCH", sourceBlockIndex=2, targetBlockIndex=4, placement={"kind": "wrap"}
    )
    await fails(
        cat, "connect_blocks", "INVALID_ARG", sourceBlockIndex=3, targetBlockIndex=7, placement={"kind": "wrap"}
    )  # not empty
    spare = (await ok(cat, "add_block", blockType="control_if"))["index"]
    message = await fails(
        cat,
        "connect_blocks",
        "CONNECTION_MISMATCH",
        sourceBlockIndex=spare,
        targetBlockIndex=1,
        placement={"kind": "wrap"},
    )
    assert "hat" in message


async def test_connect_refuses_cycles_and_bad_arguments(cat: Editor) -> None:
    await fails(
        cat, "connect_blocks", "INVALID_ARG", sourceBlockIndex=5, targetBlockIndex=6, placement={"kind": "stack_after"}
    )  # into itself
    await fails(
        cat, "connect_blocks", "INVALID_ARG", sourceBlockIndex=2, targetBlockIndex=2, placement={"kind": "stack_after"}
    )
    await fails(
        cat, "connect_blocks", "NOT_FOUND", sourceBlockIndex=2, targetBlockIndex=99, placement={"kind": "stack_after"}
    )
    await fails(
        cat,
        "connect_blocks",
        "INVALID_ARG",
        sourceBlockIndex="2",
        targetBlockIndex=3,
        placement={"kind": "stack_after"},
    )
    await fails(
        cat, "connect_blocks", "INVALID_ARG", sourceBlockIndex=2, targetBlockIndex=3, placement={"kind": "glue"}
    )
    await fails(cat, "connect_blocks", "INVALID_ARG", sourceBlockIndex=2, targetBlockIndex=3)
    assert await code(cat) == BASE_CAT  # failed actions change nothing


async def test_detach_and_delete(cat: Editor) -> None:
    await ok(cat, "detach_blocks", blockIndex=3)  # turn + say become a script of their own
    assert (await code(cat)).endswith(
        '#5 [top] motion_turnright\n- input DEGREES: 15 (math_number)\n#6 looks_say\n- input MESSAGE: "hi" (text)'
    )
    assert (await ok(cat, "detach_blocks", blockIndex=1))["detached"] is False
    assert await ok(cat, "delete_block", blockIndex=5) == {"deleted": 2}  # the block and what hangs under it
    assert await ok(cat, "delete_block", blockIndex=3) == {"deleted": 2}  # forever and its content
    assert await code(cat) == "#1 [top] event_whenflagclicked\n#2 motion_movesteps\n- input STEPS: 10 (math_number)"
    await fails(cat, "delete_block", "NOT_FOUND", blockIndex=3)
    await fails(cat, "detach_blocks", "INVALID_ARG", blockIndex=None)


async def test_set_block_field_on_fields_and_inputs(cat: Editor) -> None:
    assert (await ok(cat, "set_block_field", blockIndex=2, fieldName="STEPS", value=-7.5))["value"] == "-7.5"
    await fails(cat, "set_block_field", "INVALID_ARG", blockIndex=2, fieldName="STEPS", value="ten")
    await ok(cat, "set_block_field", blockIndex=4, fieldName="MESSAGE", value='say "hi"\n#9 [top] fake')
    style = (await ok(cat, "add_block", blockType="motion_setrotationstyle"))["index"]
    assert (await ok(cat, "set_block_field", blockIndex=style, fieldName="STYLE", value="don't rotate"))[
        "value"
    ] == "don't rotate"
    message = await fails(cat, "set_block_field", "INVALID_ARG", blockIndex=style, fieldName="STYLE", value="sideways")
    assert '"all around"' in message
    goto = (await ok(cat, "add_block", blockType="motion_goto"))["index"]
    assert (await ok(cat, "set_block_field", blockIndex=goto, fieldName="TO", value="mouse-pointer"))[
        "value"
    ] == "_mouse_"
    assert (await ok(cat, "set_block_field", blockIndex=goto, fieldName="TO", value="Dog"))["value"] == "Dog"
    message = await fails(cat, "set_block_field", "INPUT_NOT_FOUND", blockIndex=2, fieldName="DISTANCE", value=1)
    assert "STEPS" in message
    await fails(cat, "set_block_field", "INVALID_ARG", blockIndex=2, fieldName="STEPS", value=None)
    text = await code(cat)
    assert "#2 motion_movesteps\n- input STEPS: -7.5 (math_number)" in text
    assert '- input MESSAGE: "say \\"hi\\"\\n#9 [top] fake" (text)' in text  # escaped: cannot forge a line
    assert not any(line.startswith("#9 [top] fake") for line in text.splitlines())


async def test_variables_lists_and_messages_are_set_by_name(cat: Editor) -> None:
    await ok(cat, "add_variable", name="lives", scope="sprite")
    setter = (await ok(cat, "add_block", blockType="data_setvariableto", creation={"variableName": "score"}))["index"]
    await ok(cat, "set_block_field", blockIndex=setter, fieldName="VARIABLE", value="lives")
    await fails(cat, "set_block_field", "NOT_FOUND", blockIndex=setter, fieldName="VARIABLE", value="health")
    hat = (await ok(cat, "add_block", blockType="event_whenbroadcastreceived"))["index"]
    await ok(cat, "set_block_field", blockIndex=hat, fieldName="BROADCAST_OPTION", value="game over")
    send = (await ok(cat, "add_block", blockType="event_broadcast"))["index"]
    await ok(cat, "set_block_field", blockIndex=send, fieldName="BROADCAST_INPUT", value="game over")
    text = await code(cat)
    assert (
        f"#{setter} [top] data_setvariableto\n"
        '- field VARIABLE: "lives" {choices: {"variableOptions":["lives","score"]}}' in text
    )
    assert '- field BROADCAST_OPTION: "game over"' in text
    assert '- input BROADCAST_INPUT: "game over" (event_broadcast_menu)' in text
    reporter = (await ok(cat, "add_block", blockType="data_variable", creation={"variableName": "lives"}))["index"]
    await ok(
        cat,
        "connect_blocks",
        sourceBlockIndex=reporter,
        targetBlockIndex=setter,
        placement={"kind": "value_into", "inputName": "VALUE"},
    )
    message = await fails(cat, "set_block_field", "INVALID_STATE", blockIndex=setter, fieldName="VALUE", value=3)
    assert "detach" in message


@pytest.mark.parametrize(
    "request_",
    [
        {"api": "custom_js", "args": {"fn": "window.pwned = 1"}},
        {"api": "run_project", "args": {}},
        {"api": "__proto__", "args": {}},
        {"api": "toString", "args": {}},
        {"api": None, "args": {}},
        {"api": "add_block", "args": ["motion_movesteps"]},
        {"api": "add_block", "args": {"blockType": "'); window.pwned = 1; ('"}},
        {"api": "add_block", "args": {"blockType": "motion_movesteps", "creation": "x"}},
        {"api": "select_sprite", "args": {"name": "x" * 5000}},
        {"api": "set_block_field", "args": {"blockIndex": 2, "fieldName": "STEPS", "value": {"$gt": 1}}},
    ],
)
async def test_hostile_requests_are_error_envelopes_and_run_nothing(cat: Editor, request_: dict) -> None:
    envelope = await composite.execute(cat, request_["api"], request_["args"])
    assert not envelope.success
    assert envelope.error is not None
    assert envelope.error.code in {"UNKNOWN_API", "INVALID_ARG"}
    assert await code(cat) == BASE_CAT
    assert await cat.page.evaluate("() => window.pwned === undefined")
