"""Mutation operators: each mutant changes its own place only, loads, is made again the same, and does something."""

from __future__ import annotations

import json
from collections import Counter
from typing import Any

import pytest

from scratchworld_dist.kinds.audit.variants import (
    OPERATORS,
    Mutant,
    Program,
    enumerate_mutants,
    program_form,
    sample_mutants,
    structure_problems,
)
from scratchworld_dist.sb3 import Project, Sb3Archive, block, check_project, circle_costume
from tests.support.audit_projects import mutation_project

PROJECT = mutation_project()
ORIGINAL = PROJECT.to_project_json()
MUTANTS = enumerate_mutants(ORIGINAL)
PROGRAM = Program.parse(ORIGINAL)


def block_changes(before: dict[str, Any], after: dict[str, Any]) -> dict[str, tuple[set, set, set]]:
    """Per target that changed: the blocks changed, added and removed."""
    found = {}
    old_targets = {t["name"]: t["blocks"] for t in before["targets"]}
    for target in after["targets"]:
        old, new = old_targets[target["name"]], target["blocks"]
        changed = {k for k in set(old) & set(new) if old[k] != new[k]}
        added, removed = set(new) - set(old), set(old) - set(new)
        if changed or added or removed:
            found[target["name"]] = (changed, added, removed)
    return found


def expected_changes(mutant: Mutant) -> tuple[set, set, set]:
    """What the operator may change around its block: (changed, added, removed) of its target."""
    target = PROGRAM.target(mutant.target)
    block = target.block(mutant.block_id)
    if mutant.operator == "delete_statement":
        return {block.parent, block.next} - {None}, set(), set(target.subtree(block.id))
    if mutant.operator == "swap_statements":
        below = target.block(block.next)
        return {block.parent, block.id, below.id, below.next} - {None}, set(), set()
    if mutant.operator == "unwrap_forever":
        body = target.stack(block.inputs["SUBSTACK"].block_id)
        after = {body[-1], block.next} if block.next else set()  # the body's last block gets the forever's next
        return {block.parent, body[0], *after}, set(), {block.id}
    if mutant.operator == "drop_not":
        return {block.parent, block.inputs["OPERAND"].block_id}, set(), {block.id}
    return {block.id}, set(), set()


def test_every_operator_makes_mutants_of_the_project() -> None:
    made = Counter(m.operator for m in MUTANTS)
    assert set(made) == set(OPERATORS), set(OPERATORS) - set(made)


@pytest.mark.parametrize("operator", list(OPERATORS))
def test_each_mutant_changes_its_place_only(operator: str) -> None:
    for mutant in (m for m in MUTANTS if m.operator == operator):
        changes = block_changes(ORIGINAL, mutant.project)
        assert set(changes) == {mutant.target}, mutant.change
        assert changes[mutant.target] == expected_changes(mutant), mutant.change
        for before, after in zip(ORIGINAL["targets"], mutant.project["targets"], strict=True):
            rest = {k: v for k, v in before.items() if k not in ("blocks", "broadcasts")}
            assert rest == {k: v for k, v in after.items() if k not in ("blocks", "broadcasts")}
            assert set(before["broadcasts"].items()) <= set(after["broadcasts"].items())


@pytest.mark.parametrize("operator", list(OPERATORS))
def test_each_mutant_is_whole_and_loads(operator: str) -> None:
    archive = Sb3Archive(PROJECT.to_sb3())
    for mutant in (m for m in MUTANTS if m.operator == operator):
        program = Program.parse(mutant.project)
        assert structure_problems(program) == [], mutant.change
        assert check_project(archive.with_project(mutant.project)) == mutant.project
        assert program_form(program) != program_form(PROGRAM), mutant.change


def test_literal_mutants_change_one_input_to_another_value() -> None:
    literal_operators = ("number_literal", "text_literal", "loop_count", "wait_duration")
    for mutant in (m for m in MUTANTS if m.operator in literal_operators):
        cat = lambda project: next(t for t in project["targets"] if t["name"] == "Cat")["blocks"]  # noqa: E731
        old, new = cat(ORIGINAL)[mutant.block_id], cat(mutant.project)[mutant.block_id]
        differing = [n for n in old["inputs"] if old["inputs"][n] != new["inputs"][n]]
        assert len(differing) == 1 and {k: v for k, v in old.items() if k != "inputs"} == {
            k: v for k, v in new.items() if k != "inputs"
        }
        name = differing[0]
        assert mutant.change.startswith(f"{name}: ")
        assert new["inputs"][name][1][1] != old["inputs"][name][1][1]


def test_numbers_become_zero_one_negated_and_one_off() -> None:
    steps = [m for m in MUTANTS if m.operator == "number_literal" and m.change.startswith("NUM1: '10' ->")]
    assert sorted(m.change for m in steps) == sorted(f"NUM1: '10' -> {v!r}" for v in ("0", "1", "-10", "11", "9"))
    loops = sorted(m.change for m in MUTANTS if m.operator == "loop_count")
    assert loops == ["TIMES: '3' -> '2'", "TIMES: '3' -> '4'"]
    # repeat 3 made 2 or 4 by loop_count is not made again by number_literal
    assert not any(
        m.operator == "number_literal" and m.change in ("TIMES: '3' -> '2'", "TIMES: '3' -> '4'") for m in MUTANTS
    )
    texts = sorted(m.change for m in MUTANTS if m.operator == "text_literal" and "'Big'" in m.change)
    assert texts == ["MESSAGE: 'Big' -> ''", "MESSAGE: 'Big' -> 'BIG'", "MESSAGE: 'Big' -> 'Bih'"]


def test_operators_hats_messages_and_variables_change_as_named() -> None:
    changes = {m.operator: sorted(x.change for x in MUTANTS if x.operator == m.operator) for m in MUTANTS}
    assert "operator_add -> operator_mod" in changes["arithmetic_operator"]
    assert len([c for c in changes["arithmetic_operator"] if c.startswith("operator_add ->")]) == 4
    assert changes["comparison_operator"] == sorted(
        [
            "operator_gt -> operator_lt",
            "operator_gt -> operator_equals",
            "operator_lt -> operator_gt",
            "operator_lt -> operator_equals",
        ]
    )
    assert changes["boolean_operator"] == ["operator_and -> operator_or"]
    assert changes["broadcast_message"] == ["go -> stop", "stop -> go"]
    assert "event_whenkeypressed -> event_whenkeypressed up arrow" in changes["event_hat"]
    assert "event_whenbroadcastreceived -> event_whenbroadcastreceived stop" in changes["event_hat"]
    assert "event_whenflagclicked -> event_whenthisspriteclicked" in changes["event_hat"]
    # a local variable may be swapped for a global one and back; a list for the other list
    assert "VARIABLE: speed -> score" in changes["other_variable"]
    assert "VARIABLE: score -> speed" in changes["other_variable"]
    assert changes["other_list"] == ["LIST: items -> names", "STRING2: items -> names"]


def test_a_hat_moved_to_a_message_nobody_declared_declares_it() -> None:
    project = Project()
    project.sprite("Solo", costume=circle_costume("s", 5, "#000")).script(
        block("event_whenflagclicked"), block("looks_say", MESSAGE="hi")
    )
    (moved,) = [m for m in enumerate_mutants(project.to_project_json()) if "broadcastreceived" in m.change]
    stage = moved.project["targets"][0]
    hat = next(b for b in moved.project["targets"][1]["blocks"].values() if b["topLevel"])
    name, message_id = hat["fields"]["BROADCAST_OPTION"]
    assert stage["broadcasts"] == {message_id: name}
    assert structure_problems(Program.parse(moved.project)) == []


def test_the_mutated_place_is_listed_before_and_after() -> None:
    (mutant,) = [m for m in MUTANTS if m.operator == "swap_if_else"]
    assert mutant.before.startswith("== Sprite: Cat (at 40, 40), script 1\nevent_whenflagclicked")
    before, after = mutant.before.splitlines(), mutant.after.splitlines()
    assert before[before.index("else") - 1].endswith('MESSAGE="Big"')
    assert after[after.index("else") - 1].endswith('MESSAGE="small"')
    deleted = next(m for m in MUTANTS if m.operator == "delete_statement")
    assert len(deleted.after.splitlines()) == len(deleted.before.splitlines()) - 1


def test_blocks_that_never_run_are_not_mutated() -> None:
    loose = {b.id for b in PROGRAM.target("Cat").all_blocks() if b.opcode in ("looks_show",)}
    loose |= {PROGRAM.target("Cat").block(i).next for i in loose}
    assert loose and not any(m.block_id in loose for m in MUTANTS)
    assert not any("99" in m.change for m in MUTANTS)


def test_changes_that_do_nothing_are_left_out() -> None:
    project = Project()
    project.stage.variable("n", 0)
    project.sprite("S", costume=circle_costume("s", 5, "#000")).script(
        block("event_whenflagclicked"),
        block("data_setvariableto", VARIABLE="n", VALUE=0),  # 0 is never replaced by 0, nor by -0
        block("control_repeat", TIMES=0, SUBSTACK=[block("looks_nextcostume")]),  # repeat -1 runs no more than 0
        block("looks_say", MESSAGE="hi"),
        block("looks_say", MESSAGE="hi"),  # swapping two equal statements changes nothing
    )
    mutants = enumerate_mutants(project.to_project_json())
    assert [m.change for m in mutants if m.operator == "loop_count"] == ["TIMES: '0' -> '1'"]
    assert [m.change for m in mutants if m.block_id.endswith("-2") and m.operator == "number_literal"] == [
        "VALUE: '0' -> '1'",
        "VALUE: '0' -> '-1'",
    ]
    swaps = [m for m in mutants if m.operator == "swap_statements"]
    assert [m.change for m in swaps] == ["swap with next", "swap with next"]  # set/repeat and repeat/say only
    forms = [program_form(Program.parse(m.project)) for m in mutants]
    assert len(set(forms)) == len(forms)


def test_mutants_are_made_again_the_same() -> None:
    again = enumerate_mutants(mutation_project().to_project_json())
    assert [m.mutant_id for m in again] == [m.mutant_id for m in MUTANTS]
    assert [json.dumps(m.project) for m in again] == [json.dumps(m.project) for m in MUTANTS]
    assert len({m.mutant_id for m in MUTANTS}) == len(MUTANTS)


def test_sampling_is_seeded_and_spread_over_operators() -> None:
    first = sample_mutants(ORIGINAL, len(OPERATORS), seed=7)
    assert [m.mutant_id for m in first] == [m.mutant_id for m in sample_mutants(ORIGINAL, len(OPERATORS), seed=7)]
    assert Counter(m.operator for m in first) == Counter(dict.fromkeys(OPERATORS, 1))
    others = [sample_mutants(ORIGINAL, len(OPERATORS), seed=s) for s in range(1, 4)]
    assert any([m.mutant_id for m in other] != [m.mutant_id for m in first] for other in others)
    order = [m.mutant_id for m in MUTANTS]
    assert [order.index(m.mutant_id) for m in first] == sorted(order.index(m.mutant_id) for m in first)
    assert len(sample_mutants(ORIGINAL, 10_000, seed=1)) == len(MUTANTS)
    with pytest.raises(ValueError, match="cannot sample -1"):
        sample_mutants(ORIGINAL, -1, seed=1)
