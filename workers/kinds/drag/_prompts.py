"""What a drag task shows its model: one screenshot, the instruction, and how to answer with one drag.

The answer format is upstream's, ``drag(start_point='<point>x y</point>', end_point='<point>x y</point>')``,
so upstream numbers stay comparable; the words, the coordinate conventions (as in our primitive
mode, from ``model_space``) and the ``knowledge`` hints are ours. ``gt_start`` marks a feasible
start with a red ring and states it in the model's own coordinates, so the setting isolates the
choice of the drop point.
"""

from __future__ import annotations

import base64
from typing import Any

import cv2
import numpy as np

from workers.agent_api import DragSetting
from workers.agents import PRIMITIVE_POSITIONS, SCREEN, model_space
from workers.contract import CoordinateSystem
from workers.primitive import LEGEND

MARKER_RADIUS = 12
"""Radius (page px) of the ring drawn at the ``gt_start`` point: wide enough to leave the point itself visible."""

MARKER_THICKNESS = 3
MARKER_BGR = (0, 0, 255)

ANSWER_FORMAT = "drag(start_point='<point>x y</point>', end_point='<point>x y</point>')"

KNOWLEDGE = """\
# How dragging works in the Scratch editor
- Press on the block itself: its left end or a word of its label is safest. A press on a number, text field or \
dropdown drags the block too once the pointer moves, but a press on a block nested inside it (a reporter in one of \
its inputs, a block in its mouth) drags that block instead.
- On the code area, dragging a block takes every block below it in its stack along. Dragging a block out of the \
palette (the list of blocks left of the code area) makes a new copy of it.
- While it moves, the block keeps its offset from the pointer, and what has to arrive near a connection for it to \
snap is the block's own top-left corner, not the pointer. So release at: where its top-left corner must go + (press \
point - the block's top-left corner now).
- Below a block: the dragged block's top-left corner goes onto that block's bottom-left corner, on the same left \
edge. Above a block: the bottom-left corner of the dragged stack goes onto that block's top-left corner; nothing can \
go above a hat block such as "when green flag clicked".
- Into a C block (forever, repeat, if): the top-left corner goes just inside its mouth, under the top bar and right of \
its left arm; in "if ... else" the second mouth is the one under "else".
- A reporter (round ends) or boolean (pointed ends) block goes into an input slot of its own shape: its left end onto \
the slot's left end. Stack blocks never fit into inputs.
- Releasing over the palette deletes the dragged block: release inside the code area."""


def drag_messages(
    instruction: str,
    setting: DragSetting,
    screenshot_png: bytes,
    system: CoordinateSystem,
    *,
    gt_start_model: tuple[float, float] | None,
    element_text: str | None,
) -> list[dict[str, Any]]:
    """The chat messages of one drag call: the rules as the system message; the task, the ``gt_start`` hint, the
    element list and the screenshot (already marked, for ``gt_start``) as the user message.

    ``gt_start_model`` is required for ``gt_start`` and refused otherwise, so no other setting leaks a start.
    """
    if (setting == "gt_start") != (gt_start_model is not None):
        raise ValueError(f"gt_start_model is given exactly for the gt_start setting (setting {setting!r})")
    listed = element_text is not None
    seen = f"a {SCREEN[0]}x{SCREEN[1]} screenshot of the editor" + (" and a list of its elements" if listed else "")
    index_answer = (
        " Either point may instead name an element of the list by its index, written <index>N</index>"
        " (e.g. start_point='<index>12</index>')."
    )
    sections = [
        f"You use the Scratch 3 editor with the mouse. You see {seen}. Do the task with exactly one drag: the left "
        "button is pressed at the start point, the pointer moves to the end point in small steps, and the button is "
        "released there.",
        f"# Coordinates\n{convention(system)}",
        *([f"# Element list format\n{LEGEND} {PRIMITIVE_POSITIONS}"] if listed else []),
        *([KNOWLEDGE] if setting == "knowledge" else []),
        "# Answer\nReason first if you like, then end your reply with exactly one drag in this form:\n"
        f"{ANSWER_FORMAT}\nwhere each x y is a point in the coordinates above." + (index_answer if listed else ""),
    ]
    texts = [f"# Task\n{instruction}"]
    if gt_start_model is not None:
        point = f"<point>{_number(gt_start_model[0])} {_number(gt_start_model[1])}</point>"
        texts.append(
            f"# Start point\nThe red ring on the screenshot marks a point that grabs the block to drag: {point} in "
            f"your coordinates. Start the drag there (start_point='{point}') and choose where to release it."
        )
    if listed:
        texts.append(f"# Element list\n{element_text}")
    url = "data:image/png;base64," + base64.b64encode(screenshot_png).decode()
    user = [{"type": "text", "text": "\n\n".join(texts)}, {"type": "image_url", "image_url": {"url": url}}]
    return [{"role": "system", "content": "\n\n".join(sections)}, {"role": "user", "content": user}]


def convention(system: CoordinateSystem) -> str:
    """How a point is written in ``system``, with the ranges ``model_space`` gives."""
    width, height = (round(size) for size in model_space(system))
    if system == "normalized_1000":
        return (
            f"x and y are normalised to 0-{width} on both axes, whatever the image size: (0, 0) is the top-left corner "
            f"of the screenshot and ({width}, {height}) its bottom-right corner."
        )
    shown = (
        "the screenshot" if (width, height) == SCREEN else f"the screenshot as you see it, resized to {width}x{height}"
    )
    return (
        f"x and y are pixels of {shown}: x from 0 (left edge) to {width - 1}, y from 0 (top edge) to {height - 1}, "
        "with (0, 0) the top-left corner."
    )


def draw_start_marker(png: bytes, point: tuple[int, int]) -> bytes:
    """``png`` with a red ring of ``MARKER_RADIUS`` around ``point`` (page px), upstream's ``gt_start`` mark."""
    image = cv2.imdecode(np.frombuffer(png, np.uint8), cv2.IMREAD_COLOR)
    if image is None:
        raise ValueError("the screenshot is not a decodable image")
    cv2.circle(image, (int(point[0]), int(point[1])), MARKER_RADIUS, MARKER_BGR, MARKER_THICKNESS, cv2.LINE_AA)
    ok, encoded = cv2.imencode(".png", image)
    if not ok:
        raise ValueError("the marked screenshot could not be encoded as PNG")
    return encoded.tobytes()


def _number(value: float) -> str:
    """A coordinate as a model writes it: whole numbers without a decimal point."""
    return str(int(value)) if float(value).is_integer() else f"{value:.1f}"
