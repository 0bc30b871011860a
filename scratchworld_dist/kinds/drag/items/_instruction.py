"""A drag task's instruction: the source named by its text (and palette), then where it goes on the reference.

Blocks are named as the editor shows them (``scratchworld_dist.sb3.editing``'s labels), since the model sees a
screenshot, not ids.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from scratchworld_dist.sb3.editing import block_label, slot_phrase


def instruction(
    blocks: Mapping[str, Any],
    reference_id: str,
    kind: str,
    input_name: str | None,
    *,
    source: str,
    category: str | None,
    stack: bool,
    variable: bool,
) -> str:
    """What the model is told: the source by its text (and palette), then where it goes on the reference."""
    reference = block_label(blocks, reference_id)
    what = (
        f"a new “{source}” block from the {category.capitalize()} palette"
        if category
        else f"the stack starting with “{source}”"
        if stack
        else f"the “{source}” {'variable' if variable else 'block'}"
    )
    if kind == "next":
        where = f"attach it directly below “{reference}”"
    elif kind == "parent":
        where = f"attach it directly above “{reference}”"
    elif kind == "input":
        where = f"drop it into {slot_phrase(blocks, reference_id, input_name or '')} of “{reference}”"
    elif blocks[reference_id].get("opcode") == "control_if_else":
        branch = "first (“if”) branch" if kind == "substack_1" else "second (“else”) branch"
        where = f"put it into the {branch} of “{reference}”"
    else:
        where = f"put it inside the {'' if kind == 'substack_1' else 'second '}mouth of “{reference}”"
    return f"Drag {what} and {where}."
