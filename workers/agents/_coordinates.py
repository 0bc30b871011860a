"""Screen positions as models write them, mapped to page pixels before a gesture runs.

Vision models are trained on different conventions: most answer in the pixels of the image they
were shown, Qwen-VL models in 0-1000 on both axes, and UI-TARS in the pixels of the image after
its processor "smart-resized" it to a multiple of 28 (1280x720 becomes 1288x728). As in the
upstream harness, a model's name picks the convention unless the config states one.
"""

from __future__ import annotations

import math

from pydantic import JsonValue

from workers.contract import CoordinateSystem, ModelSpec

SCREEN = (1280, 720)
"""The viewport the screenshots show, in page pixels."""

SMART_RESIZE_FACTOR = 28
MIN_PIXELS = 56 * 56
MAX_PIXELS = 16384 * 28 * 28

_POINT_KEYS = (("x", "y"), ("start_x", "start_y"), ("end_x", "end_y"))
_BY_NAME: tuple[tuple[str, CoordinateSystem], ...] = (
    ("ui-tars", "smart_resize"),
    ("qwen3-vl", "normalized_1000"),
    ("qwen2.5-vl", "normalized_1000"),
    ("qwen-vl", "normalized_1000"),
    ("ecnu-vl", "normalized_1000"),
)


def coordinate_system(model: ModelSpec) -> CoordinateSystem:
    """The configured convention, else the one the model's name implies (pixels when it implies none)."""
    if model.coordinates is not None:
        return model.coordinates
    name = model.model.lower()
    return next((system for marker, system in _BY_NAME if marker in name), "pixels")


def smart_resize(width: int, height: int, factor: int = SMART_RESIZE_FACTOR) -> tuple[int, int]:
    """The size a Qwen2-VL-style processor resizes an image to: multiples of ``factor`` within the pixel bounds."""
    w, h = round(width / factor) * factor, round(height / factor) * factor
    if w * h > MAX_PIXELS:
        beta = math.sqrt(width * height / MAX_PIXELS)
        w, h = math.floor(width / beta / factor) * factor, math.floor(height / beta / factor) * factor
    elif w * h < MIN_PIXELS:
        beta = math.sqrt(MIN_PIXELS / (width * height))
        w, h = math.ceil(width * beta / factor) * factor, math.ceil(height * beta / factor) * factor
    return w, h


def model_space(system: CoordinateSystem) -> tuple[float, float]:
    """Width and height of the screen in the model's coordinates."""
    if system == "normalized_1000":
        return 1000.0, 1000.0
    if system == "smart_resize":
        width, height = smart_resize(*SCREEN)
        return float(width), float(height)
    return float(SCREEN[0]), float(SCREEN[1])


def to_page(args: dict[str, JsonValue], system: CoordinateSystem) -> dict[str, JsonValue]:
    """``args`` with every numeric x/y pair mapped to page pixels; anything else is left for validation."""
    if system == "pixels":
        return args
    width, height = model_space(system)
    mapped = dict(args)
    for x_key, y_key in _POINT_KEYS:
        x, y = args.get(x_key), args.get(y_key)
        if _is_number(x):
            mapped[x_key] = round(float(x) * SCREEN[0] / width, 1)  # type: ignore[arg-type]
        if _is_number(y):
            mapped[y_key] = round(float(y) * SCREEN[1] / height, 1)  # type: ignore[arg-type]
    return mapped


def _is_number(value: JsonValue) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)
