"""Refactorings: whole, loadable, made again the same, and (checked statically) doing what the original does."""

from __future__ import annotations

import json
from collections import Counter
from typing import Any

import pytest

from scratchworld_dist.kinds.audit.variants import (
    REFACTORINGS,
    Program,
    Refactoring,
    enumerate_refactorings,
    sample_refactorings,
    structure_problems,
)
from scratchworld_dist.sb3 import Sb3Archive, check_project, script_listing
from tests.support.audit_projects import refactoring_project, with_monitor

PROJECT = refactoring_project()
ORIGINAL = with_monitor(PROJECT.to_project_json(), "points")
REFACTORED = enumerate_refactorings(ORIGINAL)
PROGRAM = Program.parse(ORIGINAL)


def made(operator: str) -> list[Refactoring]:
    return [r for r in REFACTORED if r.operator == operator]


def target_of(project: dict[str, Any], name: str) -> dict[str, Any]:
    return next(t for t in project["targets"] if t["name"] == name)


def opcode_of(target: dict[str, Any], block_id: str) -> str:
    return target["blocks"][block_id]["opcode"]


def test_every_refactoring_is_made() -> None:
    assert set(Counter(r.operator for r in REFACTORED)) == set(REFACTORINGS)


def test_every_refactoring_is_whole_loads_and_changes_the_project() -> None:
    archive = Sb3Archive(PROJECT.to_sb3())
    for refactoring in REFACTORED:
        assert structure_problems(Program.parse(refactoring.project)) == [], refactoring.change
        assert check_project(archive.with_project(refactoring.project)) == refactoring.project
        assert json.dumps(refactoring.project) != json.dumps(ORIGINAL)


@pytest.mark.parametrize(
    ("operator", "old", "kind"), [("rename_variable", "points", "variables"), ("rename_list", "log", "lists")]
)
def test_a_renamed_global_appears_nowhere_under_its_old_name(operator: str, old: str, kind: str) -> None:
    (renamed,) = [r for r in made(operator) if r.change.startswith(f"{old} ->")]
    new = renamed.change.split(" -> ")[1]
    before, after = json.dumps(ORIGINAL), json.dumps(renamed.project)
    assert f'"{old}"' not in after
    assert after.count(f'"{new}"') == before.count(f'"{old}"') >= 2  # declared and used
    assert after.replace(f'"{new}"', f'"{old}"') == before  # nothing else changed
    assert [e[0] for e in target_of(renamed.project, "Stage")[kind].values()] == [new]


def test_a_renamed_local_changes_its_sprite_and_those_reading_it_by_name() -> None:
    (renamed,) = [r for r in made("rename_variable") if r.change.startswith("steps ->")]
    assert renamed.block_id == "variable-Dog-steps"
    owl = target_of(renamed.project, "Owl")
    reader = next(b for b in owl["blocks"].values() if b["opcode"] == "sensing_of")
    assert reader["fields"]["PROPERTY"][0] == "steps renamed"
    assert '"steps"' not in json.dumps(renamed.project)


def test_a_moved_script_changes_place_only() -> None:
    for moved in made("move_script"):
        for before, after in zip(ORIGINAL["targets"], moved.project["targets"], strict=True):
            for block_id, block in after["blocks"].items():
                old = before["blocks"][block_id]
                if block_id == moved.block_id:
                    assert (block["x"] - old["x"], block["y"] - old["y"]) == (160, 80)
                    block = {**block, "x": old["x"], "y": old["y"]}
                assert block == old


def test_only_a_script_that_shares_its_trigger_with_none_is_reordered() -> None:
    (reordered,) = made("reorder_scripts")
    dog_before, dog_after = target_of(ORIGINAL, "Dog"), target_of(reordered.project, "Dog")
    assert opcode_of(dog_before, reordered.block_id) == "event_whenbroadcastreceived"
    assert dog_after["blocks"] == dog_before["blocks"]  # the same blocks...
    tops = [k for k, b in dog_after["blocks"].items() if b["topLevel"]]
    assert tops[-1] == reordered.block_id  # ...the moved script last
    old_tops = [k for k, b in dog_before["blocks"].items() if b["topLevel"]]
    flags = [t for t in old_tops if opcode_of(dog_before, t) == "event_whenflagclicked"]
    assert [t for t in tops if t in flags] == flags  # two flag scripts keep their order
    moved = PROGRAM.target("Dog").script_blocks(reordered.block_id)
    assert list(dog_after["blocks"])[-len(moved) :] == moved  # all its blocks, in their order


def test_a_split_script_sends_its_tail_a_new_message_and_waits_for_it() -> None:
    (split,) = made("split_at_broadcast")
    dog_before, dog_after = target_of(ORIGINAL, "Dog"), target_of(split.project, "Dog")
    tail = dog_before["blocks"][split.block_id]["next"]
    sender = dog_after["blocks"][dog_after["blocks"][split.block_id]["next"]]
    assert sender["opcode"] == "event_broadcastandwait" and sender["next"] is None
    _, name, message_id = sender["inputs"]["BROADCAST_INPUT"][1]
    assert target_of(split.project, "Stage")["broadcasts"][message_id] == name
    assert name not in target_of(ORIGINAL, "Stage")["broadcasts"].values()
    hat_id = dog_after["blocks"][tail]["parent"]
    hat = dog_after["blocks"][hat_id]
    assert hat["opcode"] == "event_whenbroadcastreceived" and hat["topLevel"]
    assert hat["fields"]["BROADCAST_OPTION"] == [name, message_id]
    assert script_listing(dog_after["blocks"], tail) == script_listing(dog_before["blocks"], tail)


def test_no_split_where_clones_would_receive_the_message_too() -> None:
    (split,) = made("split_at_broadcast")
    assert split.target == "Dog"  # Owl clones itself: its broadcast and wait stays whole


def test_a_counter_loop_runs_the_same_body_as_many_times() -> None:
    (loop,) = made("counter_loop")
    dog_before, dog_after = target_of(ORIGINAL, "Dog"), target_of(loop.project, "Dog")
    blocks = dog_after["blocks"]
    repeat = blocks[loop.block_id]
    assert repeat["opcode"] == "control_repeat_until" and "TIMES" not in repeat["inputs"]
    ((var_id, (name, value)),) = [(k, v) for k, v in dog_after["variables"].items() if k not in dog_before["variables"]]
    assert value == 0
    setter = blocks[repeat["parent"]]
    assert setter["opcode"] == "data_setvariableto" and setter["fields"]["VARIABLE"] == [name, var_id]
    assert setter["inputs"]["VALUE"] == [1, [10, "0"]]
    condition = blocks[repeat["inputs"]["CONDITION"][1]]
    assert condition["opcode"] == "operator_equals"
    assert condition["inputs"]["OPERAND1"][1] == [12, name, var_id]
    assert condition["inputs"]["OPERAND2"] == [1, [10, "4"]]
    old_body = script_listing(dog_before["blocks"], dog_before["blocks"][loop.block_id]["inputs"]["SUBSTACK"][1])
    new_body = script_listing(blocks, repeat["inputs"]["SUBSTACK"][1])
    assert new_body == [*old_body, f'data_changevariableby VARIABLE={name} VALUE="1"']
    assert "(script under" not in loop.after and "control_repeat_until" in loop.after


def test_no_counter_loop_for_a_count_a_reporter_gives() -> None:
    assert [r.target for r in made("counter_loop")] == ["Dog"]  # Owl repeats (1 + 1) times


def test_no_counter_loop_nor_split_in_a_custom_block_definition() -> None:
    """A recursive call would share the counter; a block run without screen refresh would not run a split-off
    tail so. (The builder writes no custom blocks: the first script's hat is made a definition by hand.)"""
    project = json.loads(json.dumps(ORIGINAL))
    dog = target_of(project, "Dog")
    hat = next(b for b in dog["blocks"].values() if b["topLevel"] and b["opcode"] == "event_whenflagclicked")
    hat["opcode"] = "procedures_definition"
    kinds = Counter(r.operator for r in enumerate_refactorings(project))
    assert kinds["counter_loop"] == kinds["split_at_broadcast"] == 0
    assert kinds["commute_operands"] == 1  # what may be rewritten there still is


def test_operands_are_swapped_only_when_neither_has_an_effect() -> None:
    (commuted,) = made("commute_operands")
    dog_before, dog_after = target_of(ORIGINAL, "Dog"), target_of(commuted.project, "Dog")
    old, new = dog_before["blocks"][commuted.block_id], dog_after["blocks"][commuted.block_id]
    assert old["opcode"] == "operator_add"  # not points * random: random draws
    assert (new["inputs"]["NUM1"], new["inputs"]["NUM2"]) == (old["inputs"]["NUM2"], old["inputs"]["NUM1"])
    (swapped,) = made("swap_boolean_arms")
    old, new = dog_before["blocks"][swapped.block_id], target_of(swapped.project, "Dog")["blocks"][swapped.block_id]
    assert old["opcode"] == "operator_and"  # not (random = 6) or mouse down
    assert (new["inputs"]["OPERAND1"], new["inputs"]["OPERAND2"]) == (
        old["inputs"]["OPERAND2"],
        old["inputs"]["OPERAND1"],
    )


def test_refactorings_are_made_again_the_same_and_sampled_by_seed() -> None:
    again = enumerate_refactorings(with_monitor(refactoring_project().to_project_json(), "points"))
    assert [r.refactoring_id for r in again] == [r.refactoring_id for r in REFACTORED]
    assert [json.dumps(r.project) for r in again] == [json.dumps(r.project) for r in REFACTORED]
    assert len({r.refactoring_id for r in REFACTORED}) == len(REFACTORED)
    sampled = sample_refactorings(ORIGINAL, len(REFACTORINGS), seed="a")
    assert Counter(r.operator for r in sampled) == Counter(dict.fromkeys(REFACTORINGS, 1))
    assert [r.refactoring_id for r in sampled] == [r.refactoring_id for r in sample_refactorings(ORIGINAL, 8, seed="a")]
