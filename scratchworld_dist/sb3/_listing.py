"""Scripts as indented text, read from project.json blocks (no editor needed).

One line per stack block: the opcode, then its fields and inputs; reporters nest in parentheses,
C-blocks indent their substacks. Meant for reading a program (what an agent left, what a mutant
changed), not for round-tripping.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

MAX_DEPTH = 64
"""Nesting past this is cut (a hostile project could nest deeper than any reader wants)."""

_PRIMITIVES = {4, 5, 6, 7, 8, 9, 10, 11}
"""Input arrays ``[type, value]`` that hold a literal (numbers, text, colour, broadcast menu)."""


def target_listing(target: Mapping[str, Any]) -> str:
    """A target's heading, then each script (top to bottom on the workspace)."""
    name = str(target.get("name", "?"))
    head = f"== {'Stage' if target.get('isStage') else 'Sprite'}: {name}"
    blocks = target.get("blocks")
    if not isinstance(blocks, dict):
        return head
    tops = [
        (b.get("y", 0) if isinstance(b.get("y"), int | float) else 0, block_id)
        for block_id, b in blocks.items()
        if isinstance(b, dict) and b.get("topLevel") and not b.get("shadow")
    ]
    lines = [head]
    for _, block_id in sorted(tops):
        lines.append("")
        lines += script_listing(blocks, block_id)
    if len(lines) == 1:
        lines.append("(no scripts)")
    return "\n".join(lines)


@dataclass(frozen=True)
class ListedLine:
    """One line of a listing and the blocks it shows: its stack block, and the reporters and menus of its inputs
    (so a page can mark the line a block is on)."""

    text: str
    blocks: frozenset[str]


def script_listing(blocks: Mapping[str, Any], top_id: str) -> list[str]:
    """The lines of the stack that starts at ``top_id`` (following ``next``, substacks indented)."""
    return [line.text for line in script_lines(blocks, top_id)]


def script_lines(blocks: Mapping[str, Any], top_id: str) -> list[ListedLine]:
    """``script_listing`` with the blocks each line shows."""
    return _stack(blocks, top_id, 0, set())


def _stack(blocks: Mapping[str, Any], block_id: str | None, depth: int, seen: set[str]) -> list[ListedLine]:
    lines: list[ListedLine] = []
    while isinstance(block_id, str) and block_id in blocks and block_id not in seen:
        seen.add(block_id)
        block = blocks[block_id]
        if not isinstance(block, dict):
            break
        if depth >= MAX_DEPTH:
            return [*lines, ListedLine("  " * depth + "...", frozenset())]
        shown = [block_id]
        lines.append(ListedLine("  " * depth + _describe(blocks, block, depth, seen, shown), frozenset(shown)))
        for name, value in sorted(_inputs(block).items()):
            if name.startswith("SUBSTACK") and isinstance(value, list) and len(value) > 1:
                if name == "SUBSTACK2":
                    lines.append(ListedLine("  " * depth + "else", frozenset()))
                lines += _stack(blocks, value[1], depth + 1, seen)
        block_id = block.get("next")
    return lines


def _describe(blocks: Mapping[str, Any], block: dict[str, Any], depth: int, seen: set[str], shown: list[str]) -> str:
    parts = [str(block.get("opcode", "?"))]
    fields = block.get("fields")
    if isinstance(fields, dict):
        for name, value in fields.items():
            value_shown = value[0] if isinstance(value, list) and value else value
            parts.append(f"{name}={value_shown}")
    for name, value in _inputs(block).items():
        if not name.startswith("SUBSTACK"):
            parts.append(f"{name}={_input(blocks, value, depth, seen, shown)}")
    return " ".join(parts)


def _inputs(block: dict[str, Any]) -> dict[str, Any]:
    inputs = block.get("inputs")
    return inputs if isinstance(inputs, dict) else {}


def _input(blocks: Mapping[str, Any], value: Any, depth: int, seen: set[str], shown: list[str]) -> str:
    """An input's content: a literal, a variable, or a nested reporter in parentheses (its blocks added to
    ``shown``)."""
    if not isinstance(value, list) or len(value) < 2:
        return "?"
    content = value[1]
    if isinstance(content, list) and content:
        if content[0] in _PRIMITIVES and len(content) > 1:
            return json.dumps(content[1])
        if content[0] in (12, 13) and len(content) > 1:  # a variable or list reporter
            return f"({content[1]})"
        return "?"
    if isinstance(content, str) and isinstance(blocks.get(content), dict) and depth < MAX_DEPTH:
        nested = blocks[content]
        if nested.get("shadow"):  # a menu: its field is the value
            fields = nested.get("fields")
            if isinstance(fields, dict) and fields:
                shown.append(content)
                first = next(iter(fields.values()))
                return json.dumps(first[0] if isinstance(first, list) and first else first)
        if content in seen:
            return "(...)"
        seen.add(content)
        shown.append(content)
        return f"({_describe(blocks, nested, depth + 1, seen, shown)})"
    return "empty"
