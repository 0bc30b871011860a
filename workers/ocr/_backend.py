"""What every OCR backend returns and the one method it must have."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Protocol

import numpy as np
from pydantic import BaseModel, ConfigDict


class TextBox(BaseModel):
    """One line of recognised text, as an axis-aligned box in the pixels of the image that was read."""

    model_config = ConfigDict(frozen=True)

    text: str
    """The recognised text; words on one line come back as one box."""

    score: float
    """The engine's recognition confidence, 0..1."""

    x: int
    """Left edge."""

    y: int
    """Top edge."""

    width: int
    """Width in pixels."""

    height: int
    """Height in pixels."""


class OCRBackend(Protocol):
    """An OCR engine: synchronous and CPU-bound, so async callers run it in a worker thread."""

    name: str
    """Stable backend name; part of cache keys, so two engines never share results."""

    def recognize(self, image: np.ndarray) -> list[TextBox]:
        """Read the text of an HxWx3 uint8 BGR image (as cv2 gives); [] when there is none."""
        ...


def check_image(image: np.ndarray) -> None:
    """Reject anything but HxWx3 uint8, which is what the engines are fed and what the cache hashes."""
    if not isinstance(image, np.ndarray) or image.ndim != 3 or image.shape[2] != 3 or image.dtype != np.uint8:
        shape = getattr(image, "shape", None)
        dtype = getattr(image, "dtype", type(image).__name__)
        raise ValueError(f"expected an HxWx3 uint8 BGR image, got shape {shape} of {dtype}")


def box_from_quad(
    text: str, score: float, quad: Sequence[Sequence[float]] | np.ndarray, shape: tuple[int, ...]
) -> TextBox:
    """Bound a detector quad (4 points, x then y) and clamp it to the image, since unclipped quads can overhang."""
    points = np.asarray(quad, dtype=np.float64).reshape(-1, 2)
    height, width = shape[:2]
    left = min(max(round(points[:, 0].min()), 0), width)
    top = min(max(round(points[:, 1].min()), 0), height)
    right = min(max(round(points[:, 0].max()), left), width)
    bottom = min(max(round(points[:, 1].max()), top), height)
    return TextBox(text=text, score=float(score), x=left, y=top, width=right - left, height=bottom - top)
