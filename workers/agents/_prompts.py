"""What the llm agent tells its model: the system prompt of each mode and the text of each turn.

The structure follows the benchmark (task instruction, action catalog, response rule; composite
mode adds the block catalog, primitive mode the element-list legend and the coordinate
convention); the words are ours.
"""

from __future__ import annotations

import json

from pydantic import JsonValue

from workers.contract import CoordinateSystem, Mode
from workers.llm import EXPECTED_FORMAT
from workers.primitive import LEGEND

COMPOSITE_ACTIONS = """\
Actions (args in braces; indices are the #n of the Blocks Pseudocode, which change after edits):
- select_sprite {"name": str}: edit another sprite.
- select_stage {}: edit the stage.
- add_variable {"name": str, "scope": "all" | "sprite"}: create a variable (all = for all sprites).
- add_list {"name": str, "scope": "all" | "sprite"}: create a list.
- add_block {"blockType": opcode, "creation"?: {"variableName"?: str, "listName"?: str}}: add a new block as its own
  script; variable and list blocks name their variable or list in creation.
- connect_blocks {"sourceBlockIndex": int, "targetBlockIndex": int, "placement": {"kind": kind, "inputName"?: str}}
  moves the source block (a hat brings its whole script) relative to the target block:
  stack_before (above the target), stack_after (below the target), statement_into (into the target's statement input
  inputName, e.g. SUBSTACK), value_into (into the target's value or boolean input inputName), wrap (the source C block
  wraps the target and the blocks under it).
- detach_blocks {"blockIndex": int}: take a block (and the blocks under it) out of its script.
- set_block_field {"blockIndex": int, "fieldName": str, "value": str | number}: set a field or an input's literal
  value (dropdowns by choice, variable fields by name).
- delete_block {"blockIndex": int}: delete a block and the blocks under it.
- done {}: the task is complete. failed {}: give up."""

PRIMITIVE_ACTIONS = """\
Actions (a target is either "index" of the element list, or "x" and "y"):
- click {"index" | "x", "y", "button"?: "left" | "right" | "middle"}
- double_click {"index" | "x", "y"}
- drag_and_drop {"start_index" | "start_x", "start_y", "end_index" | "end_x", "end_y", "duration"?: seconds}: press,
  move in small steps and release; a block snaps when its top-left connection is dropped near a connection point.
- scroll {"direction": "up" | "down" | "left" | "right", "amount"?: pixels, "index" | "x", "y" (where to scroll)}
- type {"text": str}: type into the focused field.
- key {"key": str}: press one key (Enter, Escape, Backspace, Tab, ArrowLeft, a, ...).
- hotkey {"keys": [str, ...]}: press a combination, e.g. ["Control", "a"].
- done {}: the task is complete. failed {}: give up."""

COORDINATES: dict[CoordinateSystem, str] = {
    "pixels": "Coordinates x, y are screenshot pixels: x from 0 (left) to 1279, y from 0 (top) to 719.",
    "normalized_1000": "Coordinates x, y are normalised to 0-1000 on both axes: (0, 0) is the top-left corner of the "
    "screenshot and (1000, 1000) its bottom-right corner.",
    "smart_resize": "Coordinates x, y are in the resized screenshot you see, 1288x728 pixels: x from 0 to 1287, "
    "y from 0 to 727.",
}

PRIMITIVE_POSITIONS = "Positions in the element list are screenshot pixels (1280x720) whatever the coordinate system."

RESPONSE_RULE = (
    'Each turn, do exactly one action. Reply with your reasoning first, starting with "Analysis:", then exactly one '
    "fenced JSON block holding the action:\n" + EXPECTED_FORMAT.split("\n", 1)[1] + "\n"
    'When the task is complete, answer with {"api": "done", "args": {}}. Your project is tested after the episode '
    "whatever you answer."
)


def system_prompt(
    mode: Mode,
    instruction: str,
    *,
    block_catalog: str | None = None,
    coordinates: CoordinateSystem | None = "pixels",
    element_list: bool = True,
    workflows: str = "",
    primitive_actions: str = PRIMITIVE_ACTIONS,
) -> str:
    """The system message of an episode. ``workflows``: a learning agent's memory, shown after the actions;
    ``primitive_actions``: another agent's catalog, and ``coordinates`` None when it writes no positions."""
    if mode == "composite":
        sections = [
            "You edit a Scratch 3 project in the Scratch editor through a block-editing API. Each turn you see the "
            "editing target, the variables and lists in scope, every target of the project, and the target's blocks "
            "as pseudocode with indices #n.",
            f"# Task\n{instruction}",
            f"# {COMPOSITE_ACTIONS}",
            *_memory_section(workflows),
        ]
        if block_catalog:
            sections.append(
                "# Block catalog (opcode (shape): inputs <value|boolean>, {statement} inputs, fields [choices])\n"
                + block_catalog
            )
    else:
        seen = "a 1280x720 screenshot of the editor" + (" and a list of its elements" if element_list else "")
        sections = [
            f"You use the Scratch 3 editor with mouse and keyboard. Each turn you see {seen}.",
            f"# Task\n{instruction}",
            f"# {primitive_actions}",
            *_memory_section(workflows),
            *([COORDINATES[coordinates]] if coordinates is not None else []),
        ]
        if element_list:
            sections.append(f"{LEGEND} {PRIMITIVE_POSITIONS}")
    sections.append(f"# Response\n{RESPONSE_RULE}")
    return "\n\n".join(sections)


def _memory_section(workflows: str) -> list[str]:
    if not workflows.strip():
        return []
    guidance = "Routines that worked in earlier tasks; reuse them where they fit, filling in the placeholders."
    return [f"# Workflow memory\n{guidance}\n{workflows.strip()}"]


def result_text(ok: bool, data: JsonValue, error_code: str | None, error_message: str | None) -> str:
    """The previous action's result as the model reads it."""
    if ok:
        return "Result of your previous action: success." + (f" Data: {_compact(data)}" if data else "")
    return f"Result of your previous action: error {error_code}: {error_message}"


def _compact(data: JsonValue) -> str:
    text = json.dumps(data, ensure_ascii=False, separators=(",", ":"))
    return text if len(text) <= 500 else text[:500] + "..."
