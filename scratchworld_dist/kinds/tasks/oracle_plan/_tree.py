"""Scripts compared by what they are, not by ids or positions: a block's opcode, its field values
(variables, lists and messages by name), the literals typed into its inputs, and the blocks its
inputs hold. Two targets are the same program when their scripts are the same multiset; what still
differs is described in words, so a plan that cannot reach its golden says where."""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterator

from scratchworld_dist.kinds.tasks.oracle_plan._state import BlockState, TargetState

Canonical = tuple[object, ...]

STATEMENT_INPUT_PREFIX = "SUBSTACK"
"""C-slots (SUBSTACK, SUBSTACK2) hold stacks; every other input holds one reporter."""


def is_statement_input(name: str) -> bool:
    return name.startswith(STATEMENT_INPUT_PREFIX)


def fields_of(block: BlockState) -> tuple[tuple[str, str], ...]:
    return tuple(sorted((name, field.value) for name, field in block.fields.items()))


def literal(target: TargetState, block: BlockState, name: str) -> str | None:
    """The value typed into input ``name`` (its shadow's field), or None when it holds a block or nothing."""
    slot = block.inputs.get(name)
    if slot is None or slot.shadow is None or slot.block not in (None, slot.shadow):
        return None
    shadow = target.blocks.get(slot.shadow)
    if shadow is None or not shadow.fields:
        return None
    return next(iter(shadow.fields.values())).value


def literals_of(target: TargetState, block: BlockState) -> tuple[tuple[str, str], ...]:
    found = ((name, literal(target, block, name)) for name in sorted(block.inputs))
    return tuple((name, value) for name, value in found if value is not None)


def held_inputs(block: BlockState) -> list[tuple[str, str]]:
    """(input name, block held) for each input holding a non-shadow block, by name."""
    return [(name, held) for name in sorted(block.inputs) if (held := block.held(name)) is not None]


def chain(target: TargetState, first: str | None) -> list[str]:
    ids: list[str] = []
    while first is not None and first in target.blocks and len(ids) <= len(target.blocks):
        ids.append(first)
        first = target.blocks[first].next
    return ids


def canonical(target: TargetState, block_id: str) -> Canonical:
    """A block with everything it holds (not what follows it), as comparable data."""
    block = target.blocks[block_id]
    children = tuple((name, canonical_chain(target, held)) for name, held in held_inputs(block))
    return (block.opcode, fields_of(block), literals_of(target, block), children)


def canonical_chain(target: TargetState, first: str) -> Canonical:
    return tuple(canonical(target, block_id) for block_id in chain(target, first))


def top_blocks(target: TargetState) -> list[str]:
    """Scripts top to bottom, then left to right, then by content: never by id, which the VM may
    reassign when it loads a project again, so plans come out the same on every run."""
    tops = [b for b in target.blocks.values() if b.top_level and not b.shadow]
    tops.sort(key=lambda b: (b.y or 0.0, b.x or 0.0, repr(canonical_chain(target, b.id))))
    return [b.id for b in tops]


def preorder(target: TargetState) -> Iterator[str]:
    """Non-shadow blocks, script by script: a block, what its inputs hold, then its next."""

    def visit(first: str) -> Iterator[str]:
        for block_id in chain(target, first):
            yield block_id
            for _, held in held_inputs(target.blocks[block_id]):
                yield from visit(held)

    for top in top_blocks(target):
        yield from visit(top)


def block_order(target: TargetState) -> dict[str, int]:
    """Each block's place in ``preorder``: the tie-break wherever ids would otherwise decide."""
    return {block_id: place for place, block_id in enumerate(preorder(target))}


def scripts_of(target: TargetState) -> Counter[Canonical]:
    return Counter(canonical_chain(target, top) for top in top_blocks(target))


def script_differences(golden: TargetState, live: TargetState) -> list[str]:
    """Scripts of one side that the other lacks, named by their first block (empty: the same program)."""
    wanted, have = scripts_of(golden), scripts_of(live)
    missing, extra = wanted - have, have - wanted
    problems = [f"{golden.name}: a script starting with {_head(s)} is missing" for s in missing.elements()]
    problems += [f"{golden.name}: a script starting with {_head(s)} is not in the golden" for s in extra.elements()]
    return problems


def variable_names(target: TargetState) -> set[tuple[str, str]]:
    return {(v.type, v.name) for v in target.variables if v.type != "broadcast_msg"}


def _head(script: Canonical) -> str:
    first = script[0] if script else ("(empty)",)
    return str(first[0]) if isinstance(first, tuple) else "(empty)"  # type: ignore[index]
