"""The annotated screenshot of a drag attempt: what the model saw, with the regions and its drag drawn on.

The start region is tinted green; the end region, moved with the press (a press elsewhere on the
block moves where the drop must be by as much), blue; the press is a red dot, the release an
orange one, joined by the path the pointer took.
"""

from __future__ import annotations

import cv2
import numpy as np

from workers.contract import DragRegions, Region

_GREEN = (60, 180, 60)
_BLUE = (220, 120, 30)
_RED = (0, 0, 230)
_ORANGE = (0, 140, 255)
_ALPHA = 0.45


def _mask(region: Region, shape: tuple[int, int], dx: int = 0, dy: int = 0) -> np.ndarray:
    mask = np.zeros(shape, dtype=bool)
    height, width = shape
    for y, x0, x1 in region.rows:
        row = y + dy
        if 0 <= row < height:
            mask[row, max(0, x0 + dx) : max(0, min(width, x1 + dx + 1))] = True
    return mask


def annotate(
    png: bytes, regions: DragRegions, start: tuple[float, float] | None, end: tuple[float, float] | None
) -> bytes:
    """``png`` with the regions and the drag drawn on (regions alone when there was no drag)."""
    image = cv2.imdecode(np.frombuffer(png, np.uint8), cv2.IMREAD_COLOR)
    shape = image.shape[:2]
    shift = (0, 0)
    if start is not None:
        shift = (round(start[0]) - regions.fixed_start[0], round(start[1]) - regions.fixed_start[1])
    for mask, colour in ((_mask(regions.start, shape), _GREEN), (_mask(regions.end, shape, *shift), _BLUE)):
        image[mask] = (image[mask] * (1 - _ALPHA) + np.array(colour) * _ALPHA).astype(np.uint8)
    if start is not None and end is not None:
        a, b = (round(start[0]), round(start[1])), (round(end[0]), round(end[1]))
        cv2.line(image, a, b, _RED, 1, cv2.LINE_AA)
        cv2.circle(image, b, 5, _ORANGE, -1, cv2.LINE_AA)
        cv2.circle(image, a, 5, _RED, -1, cv2.LINE_AA)
    ok, encoded = cv2.imencode(".png", image)
    if not ok:
        raise ValueError("the annotated screenshot could not be encoded")
    return encoded.tobytes()
