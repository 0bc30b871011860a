"""The questions, in our own words: one template per kind of fact, with slots and fields named by where they
are on their block (``the left input slot``, ``the dropdown``), so the reader needs no input names.

``question(fact, facts)`` is a pure function of the fact and the view, so the validity check can write each
question again and compare it with the stored one.
"""

from __future__ import annotations

from scratchworld_dist.kinds.perception.items._facts import BlockFacts, ViewFacts
from scratchworld_dist.kinds.perception.items._item import ConnectionFact, ExistenceFact, Fact, FieldFact
from scratchworld_dist.kinds.perception.items._refs import phrase

_ORDINALS = ("first", "second", "third", "fourth", "fifth", "sixth", "seventh", "eighth")
_FIELD_WORDS = {"number": "number slot", "text": "text slot", "dropdown": "dropdown"}


def question(fact: Fact, facts: ViewFacts) -> str | None:
    """The question ``fact`` stands for in this view, or None when the view has no words for it."""
    if isinstance(fact, ConnectionFact):
        subject = phrase(fact.subject)
        if fact.relation == "above":
            return f"Is {subject} attached to the block just above it, so that the two are snapped into one stack?"
        if fact.relation == "below":
            return f"Is {subject} attached to the block just below it, so that the two are snapped into one stack?"
        if fact.parent is None or fact.slot is None:
            raise ValueError("a slot fact names its parent and slot")
        parent = facts.block(fact.parent.block)
        where = slot_words(parent, fact.slot) if parent is not None else None
        return None if where is None else f"Does {subject} sit in {where} of {phrase(fact.parent)}?"
    if isinstance(fact, ExistenceFact):
        if fact.category is not None:
            return f"Can you see any block of the {fact.name} category in the code area?"
        return f"Can you see any `{fact.name}` block in the code area?"
    return _field_question(fact, facts)


def slot_words(parent: BlockFacts, slot: str) -> str | None:
    """``the mouth``, ``the lower mouth``, ``the condition slot``, ``the right input slot``... of ``parent``."""
    own = parent.input_named(slot)
    if own is None or own.kind == "other":
        return None
    alike = [i.name for i in parent.inputs if i.kind == own.kind]
    index, count = alike.index(slot), len(alike)
    if own.kind == "statement":
        if count == 1:
            return "the mouth"
        return (
            ("the upper mouth", "the lower mouth")[index] if count == 2 else f"the {_ordinal(index)} mouth from the top"
        )
    if own.kind == "boolean":
        if count == 1:
            return "the condition slot" if parent.opcode.startswith("control_") else "the hexagonal slot"
        return _sided(index, count, "hexagonal slot")
    return "the input slot" if count == 1 else _sided(index, count, "input slot")


def field_words(block: BlockFacts, name: str) -> str | None:
    """``the number slot``, ``the right number slot``, ``the dropdown``... of ``block`` for its value ``name``."""
    own = block.field(name)
    if own is None or own.kind not in _FIELD_WORDS:
        return None
    alike = [f.name for f in block.fields if f.kind == own.kind]
    words = _FIELD_WORDS[own.kind]
    if len(alike) == 1:
        return f"the {words}"
    return _sided(alike.index(name), len(alike), words)


def _field_question(fact: FieldFact, facts: ViewFacts) -> str | None:
    block = facts.block(fact.subject.block)
    field = block.field(fact.name) if block is not None else None
    where = field_words(block, fact.name) if block is not None else None
    if field is None or where is None:
        return None
    subject = phrase(fact.subject)
    if fact.asked is None:
        what = {"number": "number", "text": "text", "dropdown": "option"}[field.kind]
        return f"Which {what} is shown in {where} of {subject}?"
    if field.kind == "number":
        return f"Does {where} of {subject} show the number {fact.asked}?"
    what = "option" if field.kind == "dropdown" else "text"
    return f"Does {where} of {subject} show the {what} `{fact.asked}`?"


def _sided(index: int, count: int, words: str) -> str:
    if count == 2:
        return f"the {('left', 'right')[index]} {words}"
    return f"the {_ordinal(index)} {words} from the left"


def _ordinal(index: int) -> str:
    return _ORDINALS[index] if index < len(_ORDINALS) else f"#{index + 1}"
