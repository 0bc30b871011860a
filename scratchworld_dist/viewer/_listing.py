"""A final project's scripts as indented text, read from its project.json (no editor needed).

One line per stack block: the opcode, then its fields and inputs; reporters nest in parentheses,
C-blocks indent their substacks. Meant for reading what an agent left, not for round-tripping.
"""

from __future__ import annotations

import io
import json
import zipfile
from typing import Any

MAX_PROJECT_JSON = 32 * 2**20
"""The largest project.json listed; a bigger one is named, not read."""

MAX_DEPTH = 64
"""Nesting past this is cut (a hostile project could nest deeper than any reader wants)."""

_PRIMITIVES = {4, 5, 6, 7, 8, 9, 10, 11}
"""Input arrays ``[type, value]`` that hold a literal (numbers, text, colour, broadcast menu)."""


def project_listing(sb3: bytes) -> str:
    """Every target's scripts, or one line saying why the project cannot be listed."""
    try:
        with zipfile.ZipFile(io.BytesIO(sb3)) as archive:
            info = archive.getinfo("project.json")
            if info.file_size > MAX_PROJECT_JSON:
                return f"project.json is {info.file_size} bytes: too large to list"
            project = json.loads(archive.read(info))
    except (zipfile.BadZipFile, KeyError, ValueError, OSError) as exc:
        return f"not a readable Scratch 3 project: {exc}"
    if not isinstance(project, dict) or not isinstance(project.get("targets"), list):
        return "not a Scratch 3 project: project.json has no targets"
    parts = [_target(t) for t in project["targets"] if isinstance(t, dict)]
    return "\n\n".join(parts) or "no targets"


def _target(target: dict[str, Any]) -> str:
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
        lines += _stack(blocks, block_id, 0, set())
    if len(lines) == 1:
        lines.append("(no scripts)")
    return "\n".join(lines)


def _stack(blocks: dict[str, Any], block_id: str | None, depth: int, seen: set[str]) -> list[str]:
    lines: list[str] = []
    while isinstance(block_id, str) and block_id in blocks and block_id not in seen:
        seen.add(block_id)
        block = blocks[block_id]
        if not isinstance(block, dict):
            break
        if depth >= MAX_DEPTH:
            return [*lines, "  " * depth + "..."]
        lines.append("  " * depth + _describe(blocks, block, depth, seen))
        for name, value in sorted(_inputs(block).items()):
            if name.startswith("SUBSTACK") and isinstance(value, list) and len(value) > 1:
                if name == "SUBSTACK2":
                    lines.append("  " * depth + "else")
                lines += _stack(blocks, value[1], depth + 1, seen)
        block_id = block.get("next")
    return lines


def _describe(blocks: dict[str, Any], block: dict[str, Any], depth: int, seen: set[str]) -> str:
    parts = [str(block.get("opcode", "?"))]
    fields = block.get("fields")
    if isinstance(fields, dict):
        for name, value in fields.items():
            shown = value[0] if isinstance(value, list) and value else value
            parts.append(f"{name}={shown}")
    for name, value in _inputs(block).items():
        if not name.startswith("SUBSTACK"):
            parts.append(f"{name}={_input(blocks, value, depth, seen)}")
    return " ".join(parts)


def _inputs(block: dict[str, Any]) -> dict[str, Any]:
    inputs = block.get("inputs")
    return inputs if isinstance(inputs, dict) else {}


def _input(blocks: dict[str, Any], value: Any, depth: int, seen: set[str]) -> str:
    """An input's content: a literal, a variable, or a nested reporter in parentheses."""
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
                first = next(iter(fields.values()))
                return json.dumps(first[0] if isinstance(first, list) and first else first)
        if content in seen:
            return "(...)"
        seen.add(content)
        return f"({_describe(blocks, nested, depth + 1, seen)})"
    return "empty"
