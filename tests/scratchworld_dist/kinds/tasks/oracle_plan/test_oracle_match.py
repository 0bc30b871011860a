"""How the oracle planner pairs golden blocks with initial ones (no browser): agreeing chains align,
a block that only moved keeps its identity, and a block of another kind is never reused."""

from __future__ import annotations

from scratchworld_dist.kinds.tasks.oracle_plan._match import match_blocks
from scratchworld_dist.kinds.tasks.oracle_plan._state import TargetState
from scratchworld_dist.kinds.tasks.oracle_plan._tree import canonical_chain, script_differences, top_blocks


def target(
    *scripts: list[tuple[str, str]], held: dict[str, tuple[str, str]] | None = None, ys: list[float] | None = None
) -> TargetState:
    """A sprite whose scripts are chains of (id, opcode); ``held``: {block: (parent, C-slot)} nests a chain."""
    blocks: dict[str, dict[str, object]] = {}
    for number, script in enumerate(scripts):
        for position, (block_id, opcode) in enumerate(script):
            blocks[block_id] = {
                "id": block_id,
                "opcode": opcode,
                "topLevel": position == 0,
                "parent": script[position - 1][0] if position else None,
                "next": script[position + 1][0] if position + 1 < len(script) else None,
                "y": (ys[number] if ys else 100 * number) if position == 0 else None,
            }
    for block_id, (parent, name) in (held or {}).items():
        blocks[block_id].update(topLevel=False, parent=parent)
        inputs = blocks[parent].setdefault("inputs", {})
        inputs[name] = {"block": block_id, "shadow": None}  # type: ignore[index]
    return TargetState.model_validate({"name": "Cat", "isStage": False, "blocks": blocks})


def test_agreeing_chains_align_and_an_inserted_block_is_left_for_adding() -> None:
    golden = target(
        [("g1", "event_whenflagclicked"), ("g2", "motion_movesteps"), ("g3", "looks_say"), ("g4", "motion_turnright")]
    )
    initial = target([("i1", "event_whenflagclicked"), ("i2", "motion_movesteps"), ("i4", "motion_turnright")])
    assert match_blocks(golden, initial) == {"g1": "i1", "g2": "i2", "g4": "i4"}


def test_a_block_in_the_wrong_place_is_kept_and_one_of_another_kind_is_not_reused() -> None:
    # golden: flag, forever { move, bounce }; initial: flag, bounce, forever { move }, and a stray turn
    golden = target(
        [("g1", "event_whenflagclicked"), ("g2", "control_forever")],
        [("g3", "motion_movesteps"), ("g4", "motion_ifonedgebounce")],
        held={"g3": ("g2", "SUBSTACK")},
    )
    initial = target(
        [("i1", "event_whenflagclicked"), ("i4", "motion_ifonedgebounce"), ("i2", "control_forever")],
        [("i3", "motion_movesteps")],
        [("i9", "motion_turnright")],
        held={"i3": ("i2", "SUBSTACK")},
    )
    assert match_blocks(golden, initial) == {"g1": "i1", "g2": "i2", "g3": "i3", "g4": "i4"}
    assert script_differences(golden, initial)  # different programs until the planner moves i4


def test_scripts_compare_by_structure_not_ids() -> None:
    one = target([("a", "event_whenflagclicked"), ("b", "motion_movesteps")])
    other = target([("x", "event_whenflagclicked"), ("y", "motion_movesteps")])
    assert canonical_chain(one, "a") == canonical_chain(other, "x")
    assert script_differences(one, other) == []
    assert script_differences(one, target([("x", "event_whenflagclicked")])) == [
        "Cat: a script starting with event_whenflagclicked is missing",
        "Cat: a script starting with event_whenflagclicked is not in the golden",
    ]


def test_ties_are_broken_by_position_never_by_id() -> None:
    """The VM may give a project's blocks new ids when it loads it again: with the ids of two equal
    candidate scripts swapped, the script higher on the workspace is still the one matched."""
    golden = target([("g1", "event_whenflagclicked"), ("g2", "looks_say")])
    for upper, lower in (("a", "z"), ("z", "a")):
        initial = target([(upper, "event_whenflagclicked")], [(lower, "event_whenflagclicked")], ys=[0, 300])
        assert top_blocks(initial) == [upper, lower]
        assert match_blocks(golden, initial)["g1"] == upper
