"""Every question worth asking about one view, each with the answer ``derive`` gives it there.

Facts are proposed generously -- every well visible block above and below, in its slot and in other slots
it would fit, every value it shows (as asked, and as another number or option), every kind and category in
view, their look-alikes and a few absent kinds -- and kept only where ``derive`` settles them and the view
has words for them. Selection (``_select``) then balances what is kept.
"""

from __future__ import annotations

import random
from collections.abc import Iterator, Sequence
from dataclasses import dataclass

from scratchworld_dist.kinds.perception.items._derive import (
    CLEAR_GAP_PX,
    Derived,
    derive,
    fits,
    gap,
    holder,
    value_problem,
)
from scratchworld_dist.kinds.perception.items._facts import BlockFacts, FieldFacts, ViewFacts
from scratchworld_dist.kinds.perception.items._item import (
    BlockReference,
    ConnectionFact,
    ExistenceFact,
    Fact,
    FieldFact,
)
from scratchworld_dist.kinds.perception.items._names import (
    ASKED_CATEGORIES,
    all_names,
    kind_name,
    look_alikes,
    opcodes_named,
)
from scratchworld_dist.kinds.perception.items._questions import question
from scratchworld_dist.kinds.perception.items._refs import reference_to
from workers.kinds.perception import QuestionKind

ABSENT_KINDS = 4
"""Kinds absent from a view that are asked about (drawn at random), besides the look-alikes of those in it."""

FAR_SLOTS = 1
"""Slots of blocks plainly apart from a reporter or stack that are asked about, per block."""


@dataclass(frozen=True)
class Candidate:
    """A question about a view, the fact it rests on and the answer the view gives it."""

    fact: Fact
    question: str
    derived: Derived

    @property
    def kind(self) -> QuestionKind:
        return self.fact.kind

    @property
    def answer_class(self) -> str:
        """YES, NO, or ``value`` for an exact value."""
        return "value" if self.derived.value_kind is not None else self.derived.answer

    @property
    def subject(self) -> str | None:
        """The block the question is mainly about (None for existence)."""
        return None if isinstance(self.fact, ExistenceFact) else self.fact.subject.block


def candidates(facts: ViewFacts, rng: random.Random) -> list[Candidate]:
    """The settled questions about ``facts``, in a deterministic order (``rng`` draws values and absent kinds)."""
    found: list[Candidate] = []
    seen: set[str] = set()
    for fact in _facts(facts, rng):
        derived = derive(fact, facts)
        text = question(fact, facts)
        if isinstance(derived, Derived) and text is not None and text not in seen:
            seen.add(text)
            found.append(Candidate(fact=fact, question=text, derived=derived))
    return found


def _facts(facts: ViewFacts, rng: random.Random) -> Iterator[Fact]:
    named = [(b, ref) for b in facts.blocks if b.well_visible and b.readable and (ref := reference_to(facts, b))]
    refs = dict((b.id, ref) for b, ref in named)
    for block, ref in named:
        yield ConnectionFact(relation="above", subject=ref)
        yield ConnectionFact(relation="below", subject=ref)
        yield from _slots(facts, block, ref, named, rng)
        for field in block.fields:
            yield from _values(field, ref, rng)
    yield from _kinds(facts, refs, rng)


def _slots(
    facts: ViewFacts,
    block: BlockFacts,
    ref: BlockReference,
    named: Sequence[tuple[BlockFacts, BlockReference]],
    rng: random.Random,
) -> Iterator[ConnectionFact]:
    """Where the block sits, the other slots of that block it would fit, and slots of other blocks near or far."""
    held = holder(facts, block)
    family = {a.id for a in facts.ancestors(block)}
    far: list[ConnectionFact] = []
    for other, other_ref in named:
        if other.id == block.id or block.id in {a.id for a in facts.ancestors(other)}:
            continue
        if other.id in family and (held is None or held[0] != other.id):
            continue  # it sits deeper inside that block: neither in its slot nor plainly out of it
        for slot in other.inputs:
            if not fits(block, slot):
                continue
            fact = ConnectionFact(relation="slot", subject=ref, parent=other_ref, slot=slot.name)
            if (held is not None and held[0] == other.id) or gap(block, other) <= CLEAR_GAP_PX:
                yield fact
            else:
                far.append(fact)
    yield from rng.sample(far, min(FAR_SLOTS, len(far)))


def _values(field: FieldFacts, ref: BlockReference, rng: random.Random) -> Iterator[FieldFact]:
    if value_problem(field) is not None:
        return
    yield FieldFact(subject=ref, name=field.name)
    if field.kind == "text":
        return
    yield FieldFact(subject=ref, name=field.name, asked=field.text)
    other = _other_number(field.text, rng) if field.kind == "number" else _other_option(field, rng)
    if other is not None:
        yield FieldFact(subject=ref, name=field.name, asked=other)


def _other_number(text: str, rng: random.Random) -> str | None:
    """A different number in the same style: as many decimals, not negative when the shown one is not."""
    try:
        value = float(text)
    except ValueError:
        return None
    decimals = len(text.partition(".")[2])
    unit = 10.0**-decimals
    choices = [value + step * unit for step in (1, 2, 5, 10, -1, -2, -5, -10)]
    choices = [c for c in choices if c != value and (c >= 0 or value < 0)]
    return f"{rng.choice(choices):.{decimals}f}" if choices else None


def _other_option(field: FieldFacts, rng: random.Random) -> str | None:
    options = [o for o in field.options or () if o != field.text and o.strip() == o and o and len(o) <= 40]
    options = [o for o in options if "`" not in o and o.isprintable() and o.lower() != field.text.lower()]
    return rng.choice(options) if options else None


def _kinds(facts: ViewFacts, refs: dict[str, BlockReference], rng: random.Random) -> Iterator[ExistenceFact]:
    """Kinds in view, their look-alikes, a few absent kinds, and every category."""
    present = sorted({ref.name for ref in refs.values()})
    in_view = {kind_name(b.opcode) for b in facts.blocks if facts.in_view(b)}
    alike = sorted({n for b in facts.blocks if b.id in refs for n in look_alikes(b.opcode)} - in_view)
    absent = [n for n in all_names() if n not in in_view and n not in alike]
    for name in [*present, *alike, *rng.sample(absent, min(ABSENT_KINDS, len(absent)))]:
        yield ExistenceFact(name=name, opcodes=opcodes_named(name))
    for category, words in ASKED_CATEGORIES.items():
        yield ExistenceFact(name=words, category=category)
