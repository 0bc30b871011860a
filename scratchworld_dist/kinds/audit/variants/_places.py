"""Where operators may change a program: the blocks that can run, the statements among them, literal values.

Only scripts under a hat run, so only they are changed: a mutant of a loose block would be a mutant no
grader can catch.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass

from scratchworld_dist.kinds.audit.variants._program import Block, Primitive, Program, Target

HATS = frozenset({"control_start_as_clone", "procedures_definition"})
"""Hats whose opcode does not say ``when``."""

CAPS = frozenset({"control_forever", "control_delete_this_clone"})
"""Blocks nothing may follow (``control_stop`` too, unless it stops only other scripts)."""

NUMBER_CODES = frozenset({4, 5, 6, 7, 8})
"""Inline literals of number slots (number, positive, whole, integer, angle)."""
TEXT_CODE = 10


def is_hat(opcode: str) -> bool:
    """A block that starts a script when something happens (``event_when...``, ``..._when...`` of extensions)."""
    return opcode in HATS or "_when" in opcode or opcode.startswith("event_when")


def is_cap(block: Block) -> bool:
    if block.opcode == "control_stop":
        return (block.extra.get("mutation") or {}).get("hasnext") != "true"
    return block.opcode in CAPS


@dataclass(frozen=True)
class Place:
    """A block that can run, in the script it belongs to."""

    target: Target
    block: Block
    top: Block


def live_places(program: Program) -> Iterator[Place]:
    """Every non-shadow block of every script under a hat: targets in order, scripts in order, each script
    from the top down (a C-block's body before the blocks after it)."""
    for target in program.targets:
        for top_id in target.scripts():
            top = target.block(top_id)
            if not is_hat(top.opcode):
                continue
            for block_id in target.script_blocks(top_id):
                block = target.block(block_id)
                if not block.shadow:
                    yield Place(target, block, top)


def is_statement(target: Target, block: Block) -> bool:
    """A stack block below a hat or another statement, or first in a C-block's substack (not a reporter)."""
    if block.parent is None or is_hat(block.opcode):
        return False
    parent = target.block(block.parent)
    if parent.next == block.id:
        return True
    return any(name.startswith("SUBSTACK") and entry.value == block.id for name, entry in parent.inputs.items())


def as_number(value: object) -> float | None:
    """The number a literal holds, if it is one (a finite decimal; blank text is no number here)."""
    if isinstance(value, bool):
        return None
    if isinstance(value, int | float):
        return float(value) if math.isfinite(value) else None
    if not isinstance(value, str) or not value.strip() or "_" in value:  # Python reads 1_000; JavaScript does not
        return None
    try:
        number = float(value)
    except ValueError:
        return None
    return number if math.isfinite(number) else None


def number_value(number: float, like: object) -> int | float | str:
    """``number`` written as the literal it replaces was: a JSON number or text, integers without ``.0``."""
    shown: int | float = int(number) if number.is_integer() and abs(number) < 1e15 else number
    if isinstance(like, int | float) and not isinstance(like, bool):
        return shown
    return str(shown)


def literal_inputs(block: Block) -> Iterator[tuple[str, Primitive]]:
    """The inputs of ``block`` that show a number or text literal."""
    for name, entry in block.inputs.items():
        literal = entry.literal
        if literal is not None and (literal.code in NUMBER_CODES or literal.code == TEXT_CODE):
            yield name, literal


def js_round(number: float) -> int:
    """JavaScript's ``Math.round`` (halves up), as the VM rounds loop counts."""
    return math.floor(number + 0.5)
