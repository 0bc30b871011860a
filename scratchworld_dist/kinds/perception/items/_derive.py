"""An item's answer (and its tag) from the facts of the view it asks about: the one derivation that both
generates items and re-checks them.

``derive(fact, facts)`` gives ``Derived`` or, when the view does not settle the question beyond doubt,
``Skip`` with the reason. A YES rests on blocks that are well visible (and readable where a kind is named);
a NO on nothing of the kind in the visible area, or on two blocks plainly apart (``connection_no_easy``) or
touching without being joined (``connection_no_hard``); what lies between is skipped.

Tags follow upstream's where the meaning is the same. Ours: ``connection_no_other_slot`` (the block sits in
another slot of the same block), ``existence_yes_category`` (a category question whose blocks can also be
read; ``existence_yes_unidentifiable`` is kept for a category told by colour alone), ``equivalence_text_yes``,
``equivalence_text_no`` and ``exact_match_text`` (a text slot's value).
"""

from __future__ import annotations

from dataclasses import dataclass

from scratchworld_dist.kinds.perception.items._facts import (
    CLEAR,
    FIELD_VISIBLE,
    BlockFacts,
    FieldFacts,
    InputFacts,
    ViewFacts,
)
from scratchworld_dist.kinds.perception.items._item import (
    BlockReference,
    ConnectionFact,
    ExistenceFact,
    Fact,
    FieldFact,
)
from scratchworld_dist.kinds.perception.items._names import (
    HATS,
    category_of,
    is_boolean_reporter,
    kind_name,
    look_alikes,
)
from scratchworld_dist.kinds.perception.items._refs import phrase, resolve
from workers.agent_api import ValueKind
from workers.kinds.perception import NO, YES

SEAM = 0.80
"""Share of the bands where two stacked blocks meet that must show to judge whether they are joined."""

TOUCH_PX = 4.0
"""Blocks this close (page px; negative: overlapping) touch."""

CLEAR_GAP_PX = 16.0
"""Blocks further apart than this are plainly apart."""

MIN_OVERLAP_PX = 8.0
"""How much two blocks must share side by side for one to be above the other."""

MAX_VALUE_CHARS = 40


@dataclass(frozen=True)
class Derived:
    answer: str
    tag: str
    value_kind: ValueKind | None = None
    """Set for an exact value (the answer is the value, not YES or NO)."""


@dataclass(frozen=True)
class Skip:
    reason: str


Derivation = Derived | Skip


def derive(fact: Fact, facts: ViewFacts) -> Derivation:
    """The answer ``facts`` give to the question ``fact`` stands for, or why they give none."""
    if facts.truncated:
        return Skip("the view has more blocks than the page reports")
    if isinstance(fact, ConnectionFact):
        return _connection(fact, facts)
    if isinstance(fact, ExistenceFact):
        return _existence(fact, facts)
    return _field(fact, facts)


def named_block(facts: ViewFacts, reference: BlockReference) -> BlockFacts | Skip:
    """The block ``reference`` names, if a reader finds exactly it and can see it well and read it."""
    block = facts.block(reference.block)
    if block is None:
        return Skip(f"block {reference.block!r} is not among the target's blocks")
    found = resolve(facts, reference)
    if found is None or found.id != block.id:
        return Skip(f"{phrase(reference)} does not single out block {reference.block!r}")
    if not block.well_visible:
        return Skip(f"{phrase(reference)}: only {block.body.share:.0%} of its body shows")
    if not block.readable:
        return Skip(f"{phrase(reference)}: its label cannot be read")
    return block


def gap(a: BlockFacts, b: BlockFacts) -> float:
    """Pixels between two bodies (negative: they overlap)."""
    ra, rb = a.rect, b.rect
    return max(ra.x - rb.right, rb.x - ra.right, ra.y - rb.bottom, rb.y - ra.bottom)


def holder(facts: ViewFacts, block: BlockFacts) -> tuple[str, str] | None:
    """The block and input ``block`` sits in: a reporter's slot, or the mouth its stack hangs in."""
    current = block
    for parent in facts.ancestors(block):
        if current.input is not None:
            return parent.id, current.input
        if block.reporter:
            return None
        current = parent
    return None


def fits(block: BlockFacts, slot: InputFacts) -> bool:
    """Whether ``block`` could be put in ``slot``: a stack in a mouth, a pointed reporter in a pointed slot."""
    if slot.kind == "statement":
        return not block.reporter and block.opcode not in HATS
    if slot.kind == "boolean":
        return block.reporter and is_boolean_reporter(block.opcode)
    return slot.kind == "value" and block.reporter


# ---------- connection ----------


def _connection(fact: ConnectionFact, facts: ViewFacts) -> Derivation:
    subject = named_block(facts, fact.subject)
    if isinstance(subject, Skip):
        return subject
    if fact.relation == "slot":
        return _slot(fact, facts, subject)
    if subject.reporter:
        return Skip("a reporter is not stacked")
    if fact.relation == "above":
        if subject.parent is not None and subject.input is not None:
            return Skip("it is the first block in a mouth: no block of its stack is above it")
        if subject.top.share < SEAM:
            return Skip("its top edge is covered")
        if subject.parent is not None:
            return _joined(facts.block(subject.parent), subject)
    else:
        if subject.next is not None:
            return _joined(subject, facts.block(subject.next))
        if facts.in_mouth(subject) or any(i.kind == "statement" and i.block for i in subject.inputs):
            return Skip("the block below it would be read as the C-block around or inside it")
        if subject.bottom.share < SEAM:
            return Skip("its bottom edge is covered")
    nearest = _nearest(facts, subject, fact.relation)
    if nearest is None or nearest > CLEAR_GAP_PX:
        return Derived(NO, "connection_no_easy")
    if nearest <= TOUCH_PX:
        return Derived(NO, "connection_no_hard")
    return Skip(f"a block is {nearest:.0f} px {fact.relation} it: near, neither touching nor plainly apart")


def _joined(upper: BlockFacts | None, lower: BlockFacts | None) -> Derivation:
    if upper is None or lower is None:
        return Skip("its neighbour is not among the target's blocks")
    if not (upper.well_visible and lower.well_visible):
        return Skip("one of the two joined blocks is mostly hidden")
    seen = upper.bottom.seen + lower.top.seen
    points = upper.bottom.points + lower.top.points
    if not points or seen / points < SEAM:
        return Skip("where the two blocks meet is covered")
    return Derived(YES, "connection_yes")


def _nearest(facts: ViewFacts, subject: BlockFacts, side: str) -> float | None:
    """The gap to the nearest block right above (or below) ``subject`` that is not part of it."""
    family = {b.id for b in facts.ancestors(subject)}
    nearest: float | None = None
    for other in facts.blocks:
        if other.id == subject.id or other.id in family or subject.id in {a.id for a in facts.ancestors(other)}:
            continue
        if not facts.in_view(other) or other.rect.overlap_x(subject.rect) < MIN_OVERLAP_PX:
            continue
        if side == "above" and other.rect.y < subject.rect.y:
            distance = subject.rect.y - other.rect.bottom
        elif side == "below" and other.rect.bottom > subject.rect.bottom:
            distance = other.rect.y - subject.rect.bottom
        else:
            continue
        nearest = distance if nearest is None else min(nearest, distance)
    return nearest


def _slot(fact: ConnectionFact, facts: ViewFacts, subject: BlockFacts) -> Derivation:
    if fact.parent is None or fact.slot is None:
        raise ValueError("a slot fact names its parent and slot")
    parent = named_block(facts, fact.parent)
    if isinstance(parent, Skip):
        return parent
    slot = parent.input_named(fact.slot)
    if slot is None or not fits(subject, slot):
        return Skip(f"{phrase(fact.parent)} has no slot {fact.slot!r} that fits {phrase(fact.subject)}")
    held = holder(facts, subject)
    if held == (parent.id, slot.name):
        return Derived(YES, "connection_yes")
    if parent.id in {a.id for a in facts.ancestors(subject)}:
        if held is not None and held[0] == parent.id:
            return Derived(NO, "connection_no_other_slot")
        return Skip("it sits deeper inside that block")
    if subject.id in {a.id for a in facts.ancestors(parent)}:
        return Skip("that block sits inside it")
    if held is not None:
        return Derived(NO, "connection_no_easy")  # it plainly sits in another block
    apart = gap(subject, parent)
    if apart <= TOUCH_PX:
        return Derived(NO, "connection_no_hard")
    if apart > CLEAR_GAP_PX:
        return Derived(NO, "connection_no_easy")
    return Skip(f"it is {apart:.0f} px from that block: near, neither touching nor plainly apart")


# ---------- existence ----------


def _existence(fact: ExistenceFact, facts: ViewFacts) -> Derivation:
    if fact.category is not None:
        return _category(fact.category, facts)
    kinds = set(fact.opcodes)
    in_view = [b for b in facts.blocks if b.opcode in kinds and facts.in_view(b)]
    seen = [b for b in in_view if b.well_visible and b.readable]
    if seen:
        clear = max(b.body.share for b in seen) >= CLEAR
        return Derived(YES, "existence_yes_clear" if clear else "existence_yes_occluded")
    if in_view:
        return Skip(f"a `{fact.name}` block is in view but too hidden to tell")
    colours = {category_of(op) for op in kinds}
    doubtful = [
        b for b in facts.blocks
        if facts.in_view(b) and category_of(b.opcode) in colours and not (b.readable or b.hidden)
    ]  # fmt: skip
    if doubtful:
        return Skip(f"a block of the same colour cannot be read, so a reader cannot rule `{fact.name}` out")
    alike = {name for op in kinds for name in look_alikes(op)}
    confusable = any(kind_name(b.opcode) in alike and b.well_visible and b.readable for b in facts.blocks)
    return Derived(NO, "existence_no_confusable" if confusable else "existence_no_absent")


def _category(category: str, facts: ViewFacts) -> Derivation:
    in_view = [b for b in facts.blocks if facts.in_view(b)]
    mine = [b for b in in_view if category_of(b.opcode) == category]
    shown = [b for b in mine if b.well_visible]
    if shown:
        # Unidentifiable: only the colour tells, every block of it that shows has its words hidden (not merely
        # under the translucent palette, where they show faintly).
        colour_only = all(b.unreadable and not facts.under_palette(b) for b in shown)
        return Derived(YES, "existence_yes_unidentifiable" if colour_only else "existence_yes_category")
    if mine:
        return Skip(f"a {category} block is in view but too hidden to tell")
    if any(category_of(b.opcode) in (None, "lists", "myBlocks") for b in in_view):
        return Skip("a block of an unasked category is in view, whose colour may pass for it")
    return Derived(NO, "existence_no_unidentifiable")


# ---------- field ----------

_FIELD_TAG = {"number": "numeric", "dropdown": "dropdown", "text": "text"}


def _field(fact: FieldFact, facts: ViewFacts) -> Derivation:
    subject = named_block(facts, fact.subject)
    if isinstance(subject, Skip):
        return subject
    field = subject.field(fact.name)
    if field is None:
        return Skip(f"{phrase(fact.subject)} shows no value {fact.name!r}")
    problem = value_problem(field)
    if problem is not None:
        return Skip(problem)
    kind: ValueKind = field.kind  # type: ignore[assignment]  # value_problem leaves number, text, dropdown
    if fact.asked is None:
        return Derived(field.text, f"exact_match_{_FIELD_TAG[kind]}", kind)
    same = same_value(kind, field.text, fact.asked)
    return Derived(YES if same else NO, f"equivalence_{_FIELD_TAG[kind]}_{'yes' if same else 'no'}")


def value_problem(field: FieldFacts) -> str | None:
    """Why a field's value cannot be asked for, or None."""
    if field.kind not in _FIELD_TAG:
        return f"{field.name} is not a number, text or dropdown"
    if field.visibility.points == 0 or field.visibility.share < FIELD_VISIBLE:
        return f"{field.name} is partly hidden"
    text = field.text
    if field.shown is not None and field.shown != text:
        return f"{field.name} is drawn shortened"
    if not text.strip() or text != text.strip() or len(text) > MAX_VALUE_CHARS:
        return f"{field.name} is empty, padded or long"
    if "`" in text or not text.isprintable():
        return f"{field.name} holds characters a question cannot quote"
    return None


def same_value(kind: ValueKind, shown: str, asked: str) -> bool:
    """Whether ``asked`` is what the field shows: numbers as numbers, options and text exactly."""
    if kind == "number":
        try:
            return float(shown) == float(asked)
        except ValueError:
            return shown == asked
    return shown == asked
