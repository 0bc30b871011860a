"""Detaching blocks from a project's scripts: one connection cut, the moved part left top-level beside its script
or deleted (as a block the palette still offers).

Drag tasks cut every connection of a script to ask it back; perception views pull a block off to show a
script that is not whole. Both cut the same way, copying only the blocks that change.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from workers.contract import ConnectionKind

SHIFT_X = 380
"""Workspace units between a script and the part cut from it (placed to its right)."""
ROW_Y = 48
"""Roughly one stack block's height in workspace units: places a cut part level with its reference."""
FAR = 20000
"""Cut parts are placed within +-FAR units, whatever coordinates a project holds."""

COMPACT_REPORTERS = {12: ("data_variable", "VARIABLE"), 13: ("data_listcontents", "LIST")}
"""A compact input's code (``[12, name, id]``) and the reporter block (opcode, field) it stands for."""


@dataclass(frozen=True)
class ScriptLink:
    """A connection found in a script: ``moved`` (with ``tail``) is what a cut takes off ``reference``."""

    kind: ConnectionKind
    reference: str
    moved: str | None
    """None for a compact reporter, which gets an id when cut."""
    tail: str | None
    top: str
    row: int
    input_name: str | None = None
    compact: tuple[int, str, str] | None = None


def cut_link(
    before: Mapping[str, Any], link: ScriptLink, flyout: bool, comments: Any
) -> tuple[dict[str, Any], str, dict[str, Any] | None]:
    """The target's blocks with ``link`` cut (copying only the blocks that change), the moved part's
    top id, and the comments if a deleted block had one.

    The moved part is left top-level to the right of its script, or deleted with its shadows when
    ``flyout`` (a drag from the palette brings it back)."""
    blocks = dict(before)
    edited: set[str] = set()

    def edit(block_id: str) -> dict[str, Any]:
        if block_id not in edited:
            blocks[block_id] = copy.deepcopy(before[block_id])
            edited.add(block_id)
        return blocks[block_id]

    top = before[link.top]
    away = (_at(top.get("x"), SHIFT_X), _at(top.get("y"), ROW_Y * link.row + 40))
    reference = edit(link.reference)
    if link.kind == "next":
        reference["next"] = None
    elif link.kind == "parent":
        edit(link.tail or "")["next"] = None
        reference.update(parent=None, topLevel=True, x=_at(top.get("x")), y=_at(top.get("y")))
        away = (away[0], _at(top.get("y")))
    else:
        entry = reference["inputs"][link.input_name]
        if link.kind == "input" and len(entry) > 2 and entry[2] is not None:
            reference["inputs"][link.input_name] = [1, entry[2]]
        else:
            del reference["inputs"][link.input_name]
    moved = link.moved
    if moved is None:
        code, name, variable_id = link.compact  # type: ignore[misc]
        moved = next(i for n in range(len(blocks) + 1) if (i := f"{link.reference}-{n}-reporter") not in blocks)
        opcode, field = COMPACT_REPORTERS[code]
        blocks[moved] = {"opcode": opcode, "next": None, "parent": None, "inputs": {}, "shadow": False}
        blocks[moved]["fields"] = {field: [name, variable_id]}
        edited.add(moved)
    if not flyout:
        edit(moved).update(parent=None, topLevel=True, x=away[0], y=away[1])
        return blocks, moved, None
    gone = set(_subtree(before, moved))
    for block_id in gone:
        del blocks[block_id]
    if isinstance(comments, dict) and any(isinstance(c, dict) and c.get("blockId") in gone for c in comments.values()):
        comments = {k: {**c, "blockId": None} if c.get("blockId") in gone else c for k, c in comments.items()}
        return blocks, moved, comments
    return blocks, moved, None


def detach(
    blocks: Mapping[str, Any], *, reference: str, moved: str, input_name: str | None, at: tuple[float, float]
) -> dict[str, Any]:
    """``blocks`` with ``moved`` (and the blocks below it) cut off ``reference`` and left top-level at ``at``
    (workspace units): from below it when ``input_name`` is None, else from that input (a shadow it covered
    shows again). The cut is the one drag tasks make; blocks that do not change are shared, not copied."""
    kind: ConnectionKind = "next" if input_name is None else "input"
    link = ScriptLink(kind, reference, moved, stack_tail(blocks, moved), reference, 0, input_name)
    cut, top, _ = cut_link(blocks, link, False, None)
    cut[top] = {**cut[top], "x": _at(at[0]), "y": _at(at[1])}
    return cut


def stack_tail(blocks: Mapping[str, Any], block_id: str) -> str:
    """The last block of the stack that starts at ``block_id`` (following ``next``)."""
    current = block_id
    while isinstance(following := blocks[current].get("next"), str):
        current = following
    return current


def _subtree(blocks: Mapping[str, Any], block_id: str) -> list[str]:
    """A block and what hangs in its inputs (for a palette-sized block: its shadows)."""
    found, todo = [], [block_id]
    while todo:
        current = todo.pop()
        block = blocks.get(current)
        if current in found or not isinstance(block, dict):
            continue
        found.append(current)
        for entry in block.get("inputs", {}).values():
            todo += [ref for ref in entry[1:3] if isinstance(ref, str)]
    return found


def _at(value: Any, shift: float = 0) -> int:
    """A coordinate ``shift`` units past ``value`` (0 when it is no number), within +-FAR."""
    ok = isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)
    return max(-FAR, min(FAR, round((value if ok else 0) + shift)))
