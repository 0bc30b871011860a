"""What a perception item shows its model: the screenshot, the question, and the one-line answer it wants.

The wording is ours (upstream's task files keep only the prompt that generated each question). The model
is told what the screenshot is and to judge by what it sees, then asked for exactly one line: YES or NO, or
the value as the block shows it. Nothing else of the item (its kind, tag or label) is shown.
"""

from __future__ import annotations

import base64
from typing import Any

from workers.agent_api import AnswerFormat, ValueKind

SYSTEM = """\
You are shown a screenshot of the Scratch 3 editor: the block palette on the left, the code area in the middle \
(the scripts of the selected sprite) and the stage on the right. Answer one question about the blocks in the code \
area, judging only by what the screenshot shows.
- Blocks are named by their visible words without their values: "move steps" is the block that reads "move (10) \
steps"; a name like "set [variable] to" marks where a dropdown sits.
- Two blocks are connected when they snap together: stacked with aligned left edges and no gap, or sitting inside \
another block's slot (the mouth of a C-shaped block such as "forever" or "if", or a round or pointed input). Blocks \
that merely touch or overlap are not connected.
- A block is visible when any part of it can be seen in the code area, even partly covered by other blocks.
- When several blocks of a kind are visible, the question picks one by its position (topmost, leftmost...)."""

FORMAT = {
    "yes_no": "Answer with one line: YES or NO, and nothing else.",
    "number": "Answer with one line: the number exactly as the block shows it, and nothing else.",
    "text": "Answer with one line: the text exactly as the block shows it (same case), and nothing else.",
    "dropdown": "Answer with one line: the option exactly as the dropdown shows it, and nothing else.",
}


def perception_messages(
    question: str, answer_format: AnswerFormat, value_kind: ValueKind | None, screenshot_png: bytes
) -> list[dict[str, Any]]:
    """The chat messages of one perception call: the rules as the system message; the question, the form of
    the answer and the screenshot as the user message."""
    form = FORMAT["yes_no" if answer_format == "yes_no" else value_kind or "text"]
    url = "data:image/png;base64," + base64.b64encode(screenshot_png).decode()
    user = [
        {"type": "text", "text": f"Question: {question}\n\n{form}"},
        {"type": "image_url", "image_url": {"url": url}},
    ]
    return [{"role": "system", "content": SYSTEM}, {"role": "user", "content": user}]
