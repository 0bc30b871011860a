"""Is a program whole, and does an edit change it: the two checks every mutant and refactoring passes.

``structure_problems`` lists what would make Scratch load a project otherwise than it reads (a ``next``
whose block does not point back, an input naming a missing block, a loop of parents, a variable used where
it is not declared). ``program_form`` is what a program does, without ids or workspace positions: two
programs with the same form run the same scripts in the same order.
"""

from __future__ import annotations

from collections.abc import Collection
from typing import Any

from scratchworld_dist.kinds.audit.variants._program import (
    BROADCAST_CODE,
    LIST_CODE,
    VARIABLE_CODE,
    Block,
    Input,
    Primitive,
    Program,
    Slot,
    Target,
)

Form = tuple[Any, ...]


def structure_problems(program: Program, only: Collection[str] | None = None) -> list[str]:
    """One line per broken link or dangling reference, naming the target and block (of the targets named
    ``only``, when given)."""
    problems: list[str] = []
    broadcasts = set(program.stage.broadcasts)
    for target in program.targets:
        if only is not None and target.name not in only:
            continue
        problems += [f"{target.name}: {p}" for p in _link_problems(target)]
        scope = {12: program.in_scope(target, "variable"), 13: program.in_scope(target, "list"), 11: broadcasts}
        problems += [f"{target.name}: {p}" for p in _reference_problems(target, scope)]
    return problems


def _link_problems(target: Target) -> list[str]:
    problems: list[str] = []
    holders: dict[str, str] = {}
    for block in target.all_blocks():
        linked = [("next", block.next)] if block.next is not None else []
        linked += [(f"input {name}", ref) for name, entry in block.inputs.items() for ref in entry.block_refs()]
        for how, ref in linked:
            child = target.blocks.get(ref)
            if not isinstance(child, Block):
                problems.append(f"block {block.id!r}: {how} names the missing block {ref!r}")
            elif child.parent != block.id:
                problems.append(f"block {block.id!r}: {how} is {ref!r}, whose parent is {child.parent!r}")
            elif ref in holders:
                problems.append(f"block {ref!r} is held by both {holders[ref]!r} and {block.id!r}")
            else:
                holders[ref] = block.id
        if block.parent is None and not block.top_level:
            problems.append(f"block {block.id!r} has no parent and is not top-level")
        if block.parent is not None and block.top_level:
            problems.append(f"block {block.id!r} is top-level but has the parent {block.parent!r}")
        if block.top_level and not block.shadow and block.position is None:
            problems.append(f"block {block.id!r} is top-level with no position")
        if block.parent is not None and holders.get(block.id, block.parent) != block.parent:
            problems.append(f"block {block.id!r} names {block.parent!r} as parent, which does not hold it")
    rooted: dict[str, bool] = {}
    for block in target.all_blocks():
        if block.parent is not None and block.id not in holders:
            problems.append(f"block {block.id!r} names {block.parent!r} as parent, which does not hold it")
        if not _rooted(target, block.id, rooted):
            problems.append(f"block {block.id!r} is its own ancestor")
    for comment_id, comment in target.comments.items():
        on = comment.get("blockId") if isinstance(comment, dict) else None
        if on is not None and not isinstance(target.blocks.get(on), Block):
            problems.append(f"comment {comment_id!r} is on the missing block {on!r}")
    return problems


def _rooted(target: Target, block_id: str, rooted: dict[str, bool]) -> bool:
    """Whether following parents up from ``block_id`` ends (``rooted`` remembers what is known)."""
    path: list[str] = []
    current: str | None = block_id
    while current is not None and current not in rooted:
        found = target.blocks.get(current)
        if current in path or not isinstance(found, Block):
            answer = current not in path
            break
        path.append(current)
        current = found.parent
    else:
        answer = True if current is None else rooted[current]
    for seen in path:
        rooted[seen] = answer
    return answer


def _reference_problems(target: Target, scope: dict[int, Any]) -> list[str]:
    problems: list[str] = []
    names = {"VARIABLE": VARIABLE_CODE, "LIST": LIST_CODE, "BROADCAST_OPTION": BROADCAST_CODE}
    for block_id, item in target.blocks.items():
        used: list[tuple[int, str | None]] = []
        if isinstance(item, Primitive):
            used.append((item.code, item.ref_id))
        else:
            used += [(names[n], f.id) for n, f in item.fields.items() if n in names and f.id is not None]
            used += [
                (slot.code, slot.ref_id)
                for entry in item.inputs.values()
                for slot in (entry.value, entry.shadow)
                if isinstance(slot, Primitive) and slot.code >= BROADCAST_CODE
            ]
        for code, ref in used:
            if ref is not None and ref not in scope[code]:
                kind = {VARIABLE_CODE: "variable", LIST_CODE: "list", BROADCAST_CODE: "broadcast"}[code]
                problems.append(f"block {block_id!r} uses the {kind} {ref!r}, declared nowhere in its scope")
    return problems


def program_form(program: Program) -> Form:
    """What the program does, as a nested tuple: per target its variables, lists and scripts in the order
    they start, each block by opcode, fields and inputs (ids and positions left out)."""
    return tuple(target_form(target) for target in program.targets)


def target_form(target: Target) -> Form:
    return (
        target.name,
        target.is_stage,
        _frozen(target.variables),
        _frozen(target.lists),
        tuple(sorted(str(name) for name in target.broadcasts.values())),
        tuple(_stack_form(target, top, 0) for top in target.scripts()),
    )


def _frozen(value: Any) -> Any:
    """JSON data as something hashable and comparable (dicts by sorted keys)."""
    if isinstance(value, dict):
        return ("{}", tuple(sorted((str(k), _frozen(v)) for k, v in value.items())))
    if isinstance(value, list):
        return tuple(_frozen(v) for v in value)
    return value


def _stack_form(target: Target, first: str, depth: int) -> Form:
    return tuple(_block_form(target, target.block(block_id), depth) for block_id in target.stack(first))


def _block_form(target: Target, block: Block, depth: int) -> Form:
    fields = tuple(sorted((name, str(f.value), f.id) for name, f in block.fields.items()))
    inputs = tuple(sorted((name, _input_form(target, entry, depth)) for name, entry in block.inputs.items()))
    mutation = _frozen(block.extra.get("mutation"))
    return (block.opcode, block.shadow, fields, inputs, mutation)


def _input_form(target: Target, entry: Input, depth: int) -> Form:
    return _slot_form(target, entry.value, depth)  # a shadow under a block is never seen nor run


def _slot_form(target: Target, slot: Slot, depth: int) -> Form:
    if isinstance(slot, Primitive):
        return ("value", slot.code, str(slot.value), slot.ref_id)
    if slot is None or not isinstance(target.blocks.get(slot), Block) or depth > 200:
        return ("empty",)
    return ("blocks", _stack_form(target, slot, depth + 1))
