"""Perception answers derived from hand-made view facts (no browser): every kind and tag, the thresholds, the
position rule, the question wording, and the re-check that catches a wrong label."""

from __future__ import annotations

import pytest

from scratchworld_dist.kinds.perception.items import (
    BlockReference,
    ConnectionFact,
    ExistenceFact,
    FieldFact,
    PerceptionItem,
)
from scratchworld_dist.kinds.perception.items._derive import Derived, Skip, derive
from scratchworld_dist.kinds.perception.items._facts import Rect, ViewFacts
from scratchworld_dist.kinds.perception.items._names import kind_name, look_alikes, opcodes_named
from scratchworld_dist.kinds.perception.items._questions import question
from scratchworld_dist.kinds.perception.items._refs import reference_to, resolve
from scratchworld_dist.kinds.perception.items._validate import recheck
from tests.support.perception_facts import block, changed, field, slot, view

# A script: when flag clicked / move (10) steps / forever { say [Hi] / if <touching [edge]?> then { turn } }
HAT = block("hat", "event_whenflagclicked", (400, 100, 110, 50), next="move")
MOVE = block(
    "move", "motion_movesteps", (400, 145, 130, 38), parent="hat", next="loop",
    fields=[field("STEPS", "number", "10", (440, 150, 20, 14))], inputs=[slot("STEPS", "value")],
)  # fmt: skip
LOOP = block(
    "loop", "control_forever", (400, 178, 200, 160), parent="move", inputs=[slot("SUBSTACK", "statement", "say")]
)
SAY = block(
    "say", "looks_say", (416, 210, 120, 38), parent="loop", input="SUBSTACK", next="if",
    fields=[field("MESSAGE", "text", "Hi", (450, 215, 20, 14))], inputs=[slot("MESSAGE", "value")],
)  # fmt: skip
IF = block(
    "if", "control_if", (416, 245, 180, 80), parent="say",
    inputs=[slot("CONDITION", "boolean", "touch"), slot("SUBSTACK", "statement", "turn")],
)  # fmt: skip
TOUCH = block(
    "touch", "sensing_touchingobject", (440, 250, 120, 30), parent="if", input="CONDITION", reporter=True,
    fields=[field("TOUCHINGOBJECTMENU", "dropdown", "edge", (500, 255, 40, 20), options=["mouse-pointer", "edge"])],
    inputs=[slot("TOUCHINGOBJECTMENU", "value")],
)  # fmt: skip
TURN = block("turn", "motion_turnright", (432, 285, 140, 38), parent="if", input="SUBSTACK")
SCRIPT = (HAT, MOVE, LOOP, SAY, IF, TOUCH, TURN)


def ref(facts: ViewFacts, block_id: str) -> BlockReference:
    found = facts.block(block_id)
    assert found is not None
    reference = reference_to(facts, found)
    assert reference is not None
    return reference


def answer(fact: ConnectionFact | ExistenceFact | FieldFact, facts: ViewFacts) -> tuple[str, str] | str:
    derived = derive(fact, facts)
    return (derived.answer, derived.tag) if isinstance(derived, Derived) else f"skip: {derived.reason}"


# ---------- connection ----------


def test_stacked_blocks_are_joined_above_and_below() -> None:
    facts = view(*SCRIPT)
    assert answer(ConnectionFact(relation="above", subject=ref(facts, "move")), facts) == ("YES", "connection_yes")
    assert answer(ConnectionFact(relation="below", subject=ref(facts, "move")), facts) == ("YES", "connection_yes")
    assert answer(ConnectionFact(relation="above", subject=ref(facts, "if")), facts) == ("YES", "connection_yes")


def test_a_hat_has_nothing_above_and_a_blocks_first_in_a_mouth_is_not_asked() -> None:
    facts = view(*SCRIPT)
    assert answer(ConnectionFact(relation="above", subject=ref(facts, "hat")), facts) == ("NO", "connection_no_easy")
    assert "first block in a mouth" in str(answer(ConnectionFact(relation="above", subject=ref(facts, "say")), facts))
    # Below the last block of a mouth sits the C-block's arm; below a C-block with a filled mouth, its first block.
    assert "C-block" in str(answer(ConnectionFact(relation="below", subject=ref(facts, "turn")), facts))
    assert "C-block" in str(answer(ConnectionFact(relation="below", subject=ref(facts, "loop")), facts))


def test_a_stack_pulled_off_and_left_touching_is_a_hard_no_and_near_but_apart_is_skipped() -> None:
    lone = block("lone", "looks_hide", (460, 400, 100, 38))
    above = block("above", "looks_show", (420, 364, 100, 38))  # its bottom overlaps lone's top by 2 px
    facts = view(lone, above)
    fact = ConnectionFact(relation="above", subject=ref(facts, "lone"))
    assert answer(fact, facts) == ("NO", "connection_no_hard")
    assert answer(ConnectionFact(relation="below", subject=ref(facts, "above")), facts) == ("NO", "connection_no_hard")
    apart = view(lone, changed(above, y=352))  # a 10 px gap
    assert "neither touching nor plainly apart" in str(answer(fact, apart))
    far = view(lone, changed(above, y=200))
    assert answer(fact, far) == ("NO", "connection_no_easy")


def test_a_covered_seam_or_a_mostly_hidden_subject_is_not_asked() -> None:
    covered = view(*[changed(b, top=0.5) if b.id == "move" else b for b in SCRIPT])
    assert "covered" in str(answer(ConnectionFact(relation="above", subject=ref(view(*SCRIPT), "move")), covered))
    hidden = view(*[changed(b, body=0.2) if b.id == "move" else b for b in SCRIPT])
    fact = ConnectionFact(relation="below", subject=BlockReference(block="move", name="move steps"))
    assert "only 20% of its body shows" in str(answer(fact, hidden))


def test_slots_yes_other_slot_and_no() -> None:
    facts = view(*SCRIPT)
    in_condition = ConnectionFact(
        relation="slot", subject=ref(facts, "touch"), parent=ref(facts, "if"), slot="CONDITION"
    )
    assert answer(in_condition, facts) == ("YES", "connection_yes")
    mouth = ConnectionFact(relation="slot", subject=ref(facts, "if"), parent=ref(facts, "loop"), slot="SUBSTACK")
    assert answer(mouth, facts) == ("YES", "connection_yes")  # the second block of the mouth's stack is in it too
    deeper = ConnectionFact(relation="slot", subject=ref(facts, "turn"), parent=ref(facts, "loop"), slot="SUBSTACK")
    assert "deeper" in str(answer(deeper, facts))
    wrong_kind = ConnectionFact(relation="slot", subject=ref(facts, "turn"), parent=ref(facts, "if"), slot="CONDITION")
    assert "no slot" in str(answer(wrong_kind, facts))

    other = block(
        "ifelse", "control_if_else", (650, 100, 180, 140),
        inputs=[slot("CONDITION", "boolean"), slot("SUBSTACK", "statement", "hide"), slot("SUBSTACK2", "statement")],
    )  # fmt: skip
    hide = block("hide", "looks_hide", (666, 140, 100, 38), parent="ifelse", input="SUBSTACK")
    facts = view(*SCRIPT, other, hide)
    upper = ConnectionFact(relation="slot", subject=ref(facts, "hide"), parent=ref(facts, "ifelse"), slot="SUBSTACK")
    lower = upper.model_copy(update={"slot": "SUBSTACK2"})
    assert answer(upper, facts) == ("YES", "connection_yes")
    assert answer(lower, facts) == ("NO", "connection_no_other_slot")
    # The `touching` reporter plainly sits in the `if`: asked about the `if then else`, a plain no.
    elsewhere = ConnectionFact(
        relation="slot", subject=ref(facts, "touch"), parent=ref(facts, "ifelse"), slot="CONDITION"
    )
    assert answer(elsewhere, facts) == ("NO", "connection_no_easy")


def test_a_reporter_left_beside_its_slot_is_a_hard_no() -> None:
    loose = changed(TOUCH, parent=None, input=None, x=520)
    emptied = changed(IF, inputs=[slot("CONDITION", "boolean"), slot("SUBSTACK", "statement", "turn")])
    facts = view(*[b for b in SCRIPT if b.id not in ("touch", "if")], emptied, loose)
    fact = ConnectionFact(relation="slot", subject=ref(facts, "touch"), parent=ref(facts, "if"), slot="CONDITION")
    assert answer(fact, facts) == ("NO", "connection_no_hard")
    far = view(*[b for b in facts.blocks if b.id != "touch"], changed(loose, y=600))
    assert answer(fact, far) == ("NO", "connection_no_easy")


# ---------- existence ----------


def test_existence_clear_occluded_absent_and_confusable() -> None:
    facts = view(*SCRIPT)
    assert answer(ExistenceFact(name="say", opcodes=opcodes_named("say")), facts) == ("YES", "existence_yes_clear")
    half = view(*[changed(b, body=0.5) if b.id == "say" else b for b in SCRIPT])
    assert answer(ExistenceFact(name="say", opcodes=("looks_say",)), half) == ("YES", "existence_yes_occluded")
    assert answer(ExistenceFact(name="think", opcodes=("looks_think",)), facts) == ("NO", "existence_no_confusable")
    assert answer(ExistenceFact(name="next costume", opcodes=("looks_nextcostume",)), facts) == (
        "NO", "existence_no_absent",
    )  # fmt: skip
    assert answer(ExistenceFact(name="turn left degrees", opcodes=("motion_turnleft",)), facts) == (
        "NO", "existence_no_confusable",
    )  # fmt: skip


def test_existence_in_between_is_skipped() -> None:
    # Partly shown but unreadable: neither a YES (cannot be read) nor a NO (something of it shows).
    unreadable = view(*[changed(b, label=0.3) if b.id == "say" else b for b in SCRIPT])
    assert "too hidden" in str(answer(ExistenceFact(name="say", opcodes=("looks_say",)), unreadable))
    # A looks block that cannot be read might be a `think`: no NO about a looks kind.
    assert "cannot rule" in str(answer(ExistenceFact(name="think", opcodes=("looks_think",)), unreadable))
    # Out of the visible area altogether: absent from the view.
    away = view(*[changed(b, x=1200) if b.id == "say" else b for b in SCRIPT])
    assert answer(ExistenceFact(name="say", opcodes=("looks_say",)), away)[0] == "NO"


def test_categories_by_colour() -> None:
    covered = view(*[changed(b, label=0.1, body=0.5) if b.id == "say" else b for b in SCRIPT])
    looks = ExistenceFact(name="Looks", category="looks")
    assert answer(looks, covered) == ("YES", "existence_yes_unidentifiable")
    assert answer(looks, view(*SCRIPT)) == ("YES", "existence_yes_category")
    half_read = view(*[changed(b, label=0.6, body=0.5) if b.id == "say" else b for b in SCRIPT])
    assert answer(looks, half_read) == ("YES", "existence_yes_category")  # its words might still be made out
    sound = ExistenceFact(name="Sound", category="sound")
    assert answer(sound, view(*SCRIPT)) == ("NO", "existence_no_unidentifiable")
    under_palette = covered.model_copy(update={"palette": Rect(x=380, y=90, width=40, height=600)})
    assert answer(looks, under_palette) == ("YES", "existence_yes_category")  # its words show faintly there
    away = view(*[changed(b, x=160, body=0, label=0) if b.id == "say" else b for b in SCRIPT])  # left of the area
    assert answer(looks, away) == ("NO", "existence_no_unidentifiable")
    assert "too hidden" in str(
        answer(looks, away.model_copy(update={"palette": Rect(x=60, y=90, width=250, height=600)}))
    )
    with_list = view(*SCRIPT, block("list", "data_deletealloflist", (700, 500, 100, 38)))
    assert "colour may pass" in str(answer(sound, with_list))


# ---------- field ----------


def test_values_exact_and_equivalent() -> None:
    facts = view(*SCRIPT)
    steps = FieldFact(subject=ref(facts, "move"), name="STEPS")
    assert derive(steps, facts) == Derived("10", "exact_match_numeric", "number")
    assert answer(steps.model_copy(update={"asked": "10.0"}), facts) == ("YES", "equivalence_numeric_yes")
    assert answer(steps.model_copy(update={"asked": "15"}), facts) == ("NO", "equivalence_numeric_no")
    menu = FieldFact(subject=ref(facts, "touch"), name="TOUCHINGOBJECTMENU")
    assert derive(menu, facts) == Derived("edge", "exact_match_dropdown", "dropdown")
    assert answer(menu.model_copy(update={"asked": "mouse-pointer"}), facts) == ("NO", "equivalence_dropdown_no")
    assert derive(FieldFact(subject=ref(facts, "say"), name="MESSAGE"), facts) == Derived(
        "Hi", "exact_match_text", "text"
    )


@pytest.mark.parametrize(
    ("change", "why"),
    [
        ({"visibility": {"seen": 15, "points": 20}}, "partly hidden"),
        ({"shown": "1…"}, "shortened"),
        ({"text": "a `quoted` word", "shown": "a `quoted` word"}, "cannot quote"),
    ],
)
def test_values_that_cannot_be_read_are_not_asked(change: dict[str, object], why: str) -> None:
    steps = MOVE.fields[0].model_validate({**MOVE.fields[0].model_dump(), **change})
    facts = view(*[changed(b, fields=[steps]) if b.id == "move" else b for b in SCRIPT])
    assert why in str(answer(FieldFact(subject=ref(facts, "move"), name="STEPS"), facts))


# ---------- names and positions ----------


def test_kinds_are_named_by_their_words_with_dropdowns_as_placeholders() -> None:
    assert kind_name("motion_movesteps") == "move steps"
    assert kind_name("data_setvariableto") == "set [variable] to"
    assert kind_name("event_whenkeypressed") == "when [key] key pressed"
    assert kind_name("sensing_touchingobject") == "touching [object]?"
    assert kind_name("looks_setsizeto") == "set size to %"
    assert (
        kind_name("data_variable") is None and kind_name("procedures_call") is None and kind_name("pen_clear") is None
    )
    assert opcodes_named("change [effect] effect by") == ("looks_changeeffectby", "sound_changeeffectby")
    assert "set x to" in look_alikes("motion_changexby")


def test_a_position_is_added_only_when_a_name_repeats_and_only_one_that_singles_out() -> None:
    first = block("a", "looks_hide", (400, 100, 100, 38))
    second = block("b", "looks_hide", (404, 300, 100, 38))
    facts = view(first, second)
    assert reference_to(facts, first) == BlockReference(block="a", name="hide", position="topmost")
    assert reference_to(facts, second) == BlockReference(block="b", name="hide", position="bottommost")
    alone = view(first)
    assert reference_to(alone, first) == BlockReference(block="a", name="hide")
    # Side by side at the same height, 3 px apart on the left: no position leads by the margin.
    beside = block("c", "looks_hide", (403, 102, 100, 38))
    assert reference_to(view(first, beside), first) is None
    # A third `hide` above the first makes "topmost" name another block.
    crowded = view(first, second, block("d", "looks_hide", (600, 91, 100, 20)))
    topmost = BlockReference(block="a", name="hide", position="topmost")
    found = resolve(crowded, topmost)
    assert found is not None and found.id == "d"
    assert "does not single out" in str(answer(ConnectionFact(relation="below", subject=topmost), crowded))


def test_questions_name_slots_and_values_by_place() -> None:
    facts = view(*SCRIPT)
    condition = ConnectionFact(relation="slot", subject=ref(facts, "touch"), parent=ref(facts, "if"), slot="CONDITION")
    assert (
        question(condition, facts)
        == "Does the `touching [object]?` block sit in the condition slot of the `if then` block?"
    )
    add = block(
        "add", "operator_add", (700, 400, 100, 30), reporter=True,
        fields=[field("NUM1", "number", "1"), field("NUM2", "number", "2")],
        inputs=[slot("NUM1", "value"), slot("NUM2", "value")],
    )  # fmt: skip
    facts = view(*SCRIPT, add)
    right = FieldFact(subject=ref(facts, "add"), name="NUM2", asked="3")
    assert question(right, facts) == "Does the right number slot of the `+` block show the number 3?"
    menu = FieldFact(subject=ref(facts, "touch"), name="TOUCHINGOBJECTMENU")
    assert question(menu, facts) == "Which option is shown in the dropdown of the `touching [object]?` block?"
    assert question(ExistenceFact(name="Looks", category="looks"), facts) == (
        "Can you see any block of the Looks category in the code area?"
    )


# ---------- the re-check ----------


def test_recheck_catches_a_wrong_label_and_a_reference_that_no_longer_holds() -> None:
    facts = view(*SCRIPT)
    fact = ConnectionFact(relation="above", subject=ref(facts, "move"))
    text = question(fact, facts)
    assert text is not None
    item = PerceptionItem(
        id="v-connection-0", kind="connection", tag="connection_yes", question=text, answer_format="yes_no",
        answer="YES", screenshot="shot.png", view="v", fact=fact,
    )  # fmt: skip
    assert recheck(item, facts) is None
    flipped = item.model_copy(update={"answer": "NO"})
    assert recheck(flipped, facts) == "its answer is 'NO' but the view gives 'YES'"
    twin = block("twin", "motion_movesteps", (700, 400, 130, 38))
    assert "does not single out" in str(recheck(item, view(*SCRIPT, twin)))
    assert recheck(item.model_copy(update={"fact": None}), facts) == "it names no fact to derive its answer from"


def test_derivation_skips_a_view_whose_facts_were_cut_short() -> None:
    facts = view(*SCRIPT).model_copy(update={"truncated": True})
    assert isinstance(derive(ExistenceFact(name="say", opcodes=("looks_say",)), facts), Skip)
