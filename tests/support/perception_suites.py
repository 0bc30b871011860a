"""Hand-made perception suites for tests: a few items of every kind about small generated screenshots."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

from scratchworld_dist.kinds.perception.items import PerceptionItem, write_perception_suite


def png(shade: int, size: tuple[int, int] = (64, 48)) -> bytes:
    """A small PNG of one grey ``shade`` (distinct shades make distinct screenshots)."""
    image = np.full((size[1], size[0], 3), shade, np.uint8)
    ok, encoded = cv2.imencode(".png", image)
    assert ok
    return encoded.tobytes()


CONNECTED = "Is the `move steps` block directly connected to the block above it?"
IN_SLOT = "Is the `turn right degrees` block placed in the body slot of the `forever` block?"
VISIBLE = "Is there any `{}` block that is visible in the canvas?"
SHOWN = "What {} is shown in the {} field of the `{}` block?"
SELECTED = "What option is selected in the dropdown field of the `go to [destination]` block?"
EQUAL = "Is the numeric field in the `wait seconds` block equal to 1?"

ITEMS: tuple[tuple[str, str, str, str, str | None, str], ...] = (
    # id, kind, tag, question, value kind (None: YES/NO), answer
    ("c-yes", "connection", "connection_yes", CONNECTED, None, "YES"),
    ("c-no", "connection", "connection_no_hard", IN_SLOT, None, "NO"),
    ("e-yes", "existence", "existence_yes_clear", VISIBLE.format("say"), None, "YES"),
    ("e-no", "existence", "existence_no_absent", VISIBLE.format("sensing"), None, "NO"),
    ("f-num", "field", "exact_match_numeric", SHOWN.format("number", "numeric", "move steps"), "number", "-10"),
    ("f-drop", "field", "exact_match_dropdown", SELECTED, "dropdown", "random position"),
    ("f-text", "field", "exact_match_text", SHOWN.format("text", "text", "say"), "text", "Hello!"),
    ("f-eq", "field", "equivalence_numeric_yes", EQUAL, None, "YES"),
)
"""Eight items over three screenshots: YES share 3/8."""


def write_suite(folder: Path, name: str = "tiny-perception") -> Path:
    """The eight ``ITEMS`` as a suite of our format at ``folder`` (screenshots: three shades)."""
    shots = folder.parent / f"{folder.name}-shots"
    shots.mkdir(parents=True, exist_ok=True)
    items = []
    for index, (item_id, kind, tag, question, value_kind, answer) in enumerate(ITEMS):
        shot = shots / f"{index % 3}.png"
        shot.write_bytes(png(40 + 80 * (index % 3)))
        items.append(
            PerceptionItem.model_validate(
                {
                    "id": item_id,
                    "kind": kind,
                    "tag": tag,
                    "question": question,
                    "answer_format": "yes_no" if value_kind is None else "value",
                    "value_kind": value_kind,
                    "answer": answer,
                    "screenshot": shot,
                }
            )
        )
    return write_perception_suite(items, [], folder, name)
