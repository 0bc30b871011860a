"""Naming one block so that a reader of the screenshot finds it: its kind's name, and a position only when
needed.

A block whose kind is the only one of its name in the visible area is named plainly (the `say` block).
When other blocks of the name are in view (even partly covered), the question adds the one position --
topmost, bottommost, leftmost or rightmost, tried in that order -- at which the block beats every other
of its name by ``POSITION_MARGIN_PX``; when none does, the block is not asked about. ``resolve`` reads a
reference back the same way, so the validity check can tell whether it still singles out its block.
"""

from __future__ import annotations

from scratchworld_dist.kinds.perception.items._facts import BlockFacts, ViewFacts
from scratchworld_dist.kinds.perception.items._item import BlockReference, Position
from scratchworld_dist.kinds.perception.items._names import kind_name

POSITIONS: tuple[Position, ...] = ("topmost", "bottommost", "leftmost", "rightmost")

POSITION_MARGIN_PX = 8.0
"""How far (page px) a block must lead every other of its name for a position to single it out."""


def namesakes(facts: ViewFacts, name: str) -> list[BlockFacts]:
    """The blocks in the visible area (shown or covered) that a question would call ``name``."""
    return [b for b in facts.blocks if facts.in_view(b) and kind_name(b.opcode) == name]


def reference_to(facts: ViewFacts, block: BlockFacts) -> BlockReference | None:
    """How a question names ``block``, or None when its kind has no name or no position singles it out."""
    name = kind_name(block.opcode)
    if name is None or not facts.in_view(block):
        return None
    others = [b for b in namesakes(facts, name) if b.id != block.id]
    if not others:
        return BlockReference(block=block.id, name=name)
    for position in POSITIONS:
        if _leads(block, others, position):
            return BlockReference(block=block.id, name=name, position=position)
    return None


def resolve(facts: ViewFacts, reference: BlockReference) -> BlockFacts | None:
    """The block a reader finds by ``reference`` in this view, or None when it names none or several."""
    candidates = namesakes(facts, reference.name)
    if reference.position is None:
        return candidates[0] if len(candidates) == 1 else None
    position = reference.position
    found = [b for b in candidates if _leads(b, [o for o in candidates if o.id != b.id], position)]
    return found[0] if len(found) == 1 else None


def phrase(reference: BlockReference) -> str:
    """``the `say` block``, ``the topmost `say` block``."""
    where = f"{reference.position} " if reference.position else ""
    return f"the {where}`{reference.name}` block"


def _edge(block: BlockFacts, position: Position) -> float:
    """How far ``block`` is from the given side: smaller is further that way."""
    r = block.rect
    return {"topmost": r.y, "bottommost": -r.bottom, "leftmost": r.x, "rightmost": -r.right}[position]


def _leads(block: BlockFacts, others: list[BlockFacts], position: Position) -> bool:
    mine = _edge(block, position)
    return all(_edge(other, position) - mine >= POSITION_MARGIN_PX for other in others)
