"""What the AWM agent asks its model besides acting: the self-evaluation and the workflow induction.

The structure follows Agent Workflow Memory as the benchmark runs it (a two-line verdict read
from its ``Status:`` line; workflows of two steps or more with placeholders, from at most ten
successful trajectories, with a one-shot example per mode); the words are ours.
"""

from __future__ import annotations

import base64
import json
import re
from typing import Any

from pydantic import BaseModel, ConfigDict

from workers.contract import CompositeObservation, Mode, Observation, PrimitiveObservation

JUDGE_SYSTEM = """\
You review the work of an agent that edits projects in the Scratch 3 editor. Its tasks are of four kinds: \
create (build a project), debug (fix a broken one), extend (add to a working one) and compute (make the \
project calculate an answer). From the task, the agent's actions and the last state it saw, decide whether \
the task was accomplished. Answer in exactly two lines:
Thoughts: <your reasoning>
Status: "success" or "failure\""""

INDUCTION_RULES = """\
Below are trajectories of an agent that accomplished tasks in the Scratch 3 editor: each is the task, then \
the agent's thoughts and actions. Find the sub-routines that recur across tasks and write each as a \
reusable workflow of at least two steps. Workflows must not overlap. Replace the parts that vary \
(sprite names, values, coordinates, indices) with descriptive placeholders in braces. Cover as many tasks as \
you can. Answer with the workflows only, starting at "Workflow 1:"."""

ONE_SHOT: dict[Mode, str] = {
    "composite": """\
Example.
Query: Make the cat say Hello when the green flag is clicked.
Actions:
thought: The cat must react to the green flag; I add the hat block.
action: {"api": "add_block", "args": {"blockType": "event_whenflagclicked"}}
thought: Now the say block.
action: {"api": "add_block", "args": {"blockType": "looks_say"}}
thought: Put it under the hat.
action: {"api": "connect_blocks", "args": {"sourceBlockIndex": 2, "targetBlockIndex": 1, \
"placement": {"kind": "stack_after"}}}
thought: Set the message.
action: {"api": "set_block_field", "args": {"blockIndex": 2, "fieldName": "MESSAGE", "value": "Hello"}}
Workflows:
Workflow 1: Start a script on the green flag
add_block {"blockType": "event_whenflagclicked"} -> #{hat}
add_block {"blockType": "{opcode}"} -> #{block}
connect_blocks {"sourceBlockIndex": {block}, "targetBlockIndex": {hat}, "placement": {"kind": "stack_after"}}
Workflow 2: Set a block's value
set_block_field {"blockIndex": {block}, "fieldName": "{FIELD}", "value": "{value}"}""",
    "primitive": """\
Example.
Query: Make the cat move 10 steps when the green flag is clicked.
Actions:
thought: Open the Events category.
action: {"api": "click", "args": {"index": 12}}
thought: Drag the green-flag hat into the scripts area.
action: {"api": "drag_and_drop", "args": {"start_index": 40, "end_x": 700, "end_y": 200}}
thought: Open Motion and drag "move 10 steps" under the hat.
action: {"api": "click", "args": {"index": 10}}
action: {"api": "drag_and_drop", "args": {"start_index": 31, "end_x": 702, "end_y": 236}}
Workflows:
Workflow 1: Add a block from a category under a script
click {"index": {category button}}
drag_and_drop {"start_index": {palette block}, "end_x": {script x}, "end_y": {bottom of the script's last block}}
Workflow 2: Type a value into a block's input
click {"x": {input x}, "y": {input y}}
hotkey {"keys": ["Control", "a"]}
type {"text": "{value}"}""",
}


class Trail(BaseModel):
    """What AWM keeps of a successful episode: the task and its thought/action lines."""

    model_config = ConfigDict(frozen=True, extra="ignore")

    task: str
    trajectory: str


def trail_lines(thought: str, action: dict[str, Any] | None) -> str:
    lines = [f"thought: {' '.join(thought.split())}"] if thought.strip() else []
    if action is not None:
        lines.append(f"action: {json.dumps(action, ensure_ascii=False)}")
    return "\n".join(lines)


def judge_messages(
    mode: Mode, instruction: str, actions: list[dict[str, Any]], final_reply: str, last: Observation | None
) -> list[dict[str, Any]]:
    """The self-evaluation call: the task, the numbered actions, the last reply and the last state seen."""
    numbered = "\n".join(f"{n}. {json.dumps(a, ensure_ascii=False)}" for n, a in enumerate(actions, 1)) or "(none)"
    text = (
        f"Task: {instruction}\n\nActions taken:\n{numbered}\n\nThe agent's last reply:\n{final_reply or '(none)'}"
        "\n\nThe last state the agent saw (before its last action):\n"
    )
    if isinstance(last, CompositeObservation):
        return [{"role": "system", "content": JUDGE_SYSTEM}, {"role": "user", "content": text + last.text}]
    if isinstance(last, PrimitiveObservation):
        url = "data:image/png;base64," + base64.b64encode(last.screenshot_png).decode()
        content = [{"type": "text", "text": text + last.text}, {"type": "image_url", "image_url": {"url": url}}]
        return [{"role": "system", "content": JUDGE_SYSTEM}, {"role": "user", "content": content}]
    return [{"role": "system", "content": JUDGE_SYSTEM}, {"role": "user", "content": text + "(nothing observed)"}]


_STATUS = re.compile(r"^\s*status\s*:\s*(.+?)\s*$", re.I | re.M)


def judged_success(reply: str) -> bool:
    """The verdict of the ``Status:`` line: success only when it says exactly that (quotes aside)."""
    found = _STATUS.findall(reply)
    return bool(found) and found[-1].strip().strip("\"'*` ").lower() == "success"


def induction_prompt(mode: Mode, trails: list[Trail]) -> str:
    shown = "\n\n".join(f"Query: {t.task}\nActions:\n{t.trajectory}" for t in trails)
    return f"{INDUCTION_RULES}\n\n{ONE_SHOT[mode]}\n\n# Successful trajectories\n\n{shown}"


def workflows_of(reply: str) -> str:
    """The workflows of an induction reply (from "Workflow 1" on when the model wrote a preamble)."""
    start = reply.find("Workflow 1")
    return (reply[start:] if start >= 0 else reply).strip()
