"""Colour fields: Scratch's colour picker, driven through its three sliders to an exact colour.

A click on a colour field opens a picker of three range inputs (hue, saturation, brightness). Each
input event sets the field to ``hsvToHex(hue, saturation, brightness)`` of the sliders' current
values, the untouched ones keeping what the picker derived from the old colour (fractions that no
slider position holds). So every slider gets at least one input event, and the three values are
chosen on the sliders' own grids so that Blockly's conversion gives the wanted colour exactly. A
colour no setting gives (the grids are coarse) is picked from the stage with the eyedropper, where
the stage shows it.
"""

from __future__ import annotations

import math
from collections.abc import AsyncIterator

from workers.agents._primitive_oracle._divergence import OracleDivergenceError
from workers.agents._primitive_oracle._geometry import ColourSlider, Point, Rect
from workers.agents._primitive_oracle._gestures import click
from workers.agents._primitive_oracle._page import Page
from workers.contract import PrimitiveAction

SLIDER_NAMES = ("hue", "saturation", "brightness")
KEY_STEPS = 12
"""Slider steps worth arrow keys; a value farther off is clicked at (again)."""
MAX_GESTURES = 40
"""Gestures one slider may take before the oracle gives up on it."""


def hsv_to_hex(hue: float, saturation: float, value: float) -> str:
    """Blockly's ``utils.colour.hsvToHex``, operation for operation (the picker's conversion)."""
    if saturation == 0:
        red = green = blue = value
    else:
        sextant = math.floor(hue / 60)
        remainder = hue / 60 - sextant
        val1 = value * (1 - saturation)
        val2 = value * (1 - saturation * remainder)
        val3 = value * (1 - saturation * (1 - remainder))
        red, green, blue = {
            1: (val2, value, val1),
            2: (val1, value, val3),
            3: (val1, val2, value),
            4: (val3, val1, value),
            5: (value, val1, val2),
        }.get(sextant, (value, val3, val1))
    return "#" + "".join(f"{math.floor(channel):02x}" for channel in (red, green, blue))


def rgb_to_hsv(red: int, green: int, blue: int) -> tuple[float, float, float]:
    """The picker's own ``rgbToHsv`` (hue in degrees, saturation 0-1, value 0-255)."""
    high, low = max(red, green, blue), min(red, green, blue)
    if high == low:
        return 0.0, 0.0, float(high)
    spread = high - low
    if red == high:
        hue = (green - blue) / spread
    elif green == high:
        hue = 2 + (blue - red) / spread
    else:
        hue = 4 + (red - green) / spread
    hue *= 60
    hue = hue + 360 if hue < 0 else hue - 360 if hue > 360 else hue
    return hue, spread / high, float(high)


def grid(slider: ColourSlider) -> list[float]:
    """Every value the slider can hold (its step from its minimum, as a range input snaps)."""
    count = round((slider.max - slider.min) / slider.step)
    # Values as the input's text parses: k/1000, not k*0.001 (the two differ in the last bit).
    scale = round(1 / slider.step) if slider.step < 1 else None
    return [
        (round(slider.min * scale) + k) / scale if scale else slider.min + k * slider.step for k in range(count + 1)
    ]


def slider_values(colour: str, sliders: list[ColourSlider]) -> tuple[float, float, float] | None:
    """Hue, saturation and brightness on the sliders' grids that give exactly ``colour`` (``#rrggbb``);
    of several, the one nearest the colour's own HSV; None when no setting gives it."""
    try:
        red, green, blue = (int(colour[i : i + 2], 16) for i in (1, 3, 5))
    except ValueError:
        return None
    if len(colour) != 7 or not colour.startswith("#"):
        return None
    wanted = colour.lower()
    hues, saturations, values = (grid(slider) for slider in sliders)
    high, low = max(red, green, blue), min(red, green, blue)
    if high == low and 0 in saturations and high in values:
        return hues[0], 0.0, float(high)  # a grey: no saturation, any hue
    own_hue, own_saturation, _ = rgb_to_hsv(red, green, blue)
    best: tuple[float, tuple[float, float, float]] | None = None
    for value in (v for v in values if math.floor(v) == high):
        for saturation in (s for s in saturations if s == 0 or math.floor(value * (1 - s)) == low):
            for hue in hues:
                if hsv_to_hex(hue, saturation, value) != wanted:
                    continue
                turn = abs(hue - own_hue)
                distance = min(turn, 360 - turn) / 360 + abs(saturation - own_saturation)
                if best is None or distance < best[0]:
                    best = (distance, (hue, saturation, value))
    return best[1] if best else None


async def pick_colour(page: Page, colour: str, what: str) -> AsyncIterator[PrimitiveAction]:
    """In the open colour picker, set the three sliders so that the field holds ``colour``."""
    await page.wait("colourPickerOpen", what="the colour picker to open")
    picker = await page.colour_picker()
    targets = slider_values(colour, picker.sliders)
    if targets is None:
        async for gesture in _eyedrop(page, colour, picker.eyedropper, what):
            yield gesture
        return
    for index, target in enumerate(targets):
        async for gesture in _set_slider(page, index, target, what):
            yield gesture


async def _set_slider(page: Page, index: int, target: float, what: str) -> AsyncIterator[PrimitiveAction]:
    """Click the slider near ``target`` (which focuses it), then step it with arrow keys; its last
    gesture must have moved it (an input event), or the picker may still hold a fraction."""
    slider = await _slider(page, index)
    rect, span = slider.rect, slider.max - slider.min
    travel = max(1.0, rect.width - rect.height)  # the thumb (about as wide as the slider is high) between the ends
    x = rect.x + rect.height / 2 + (target - slider.min) / span * travel
    clicked, moved = False, False
    for _ in range(MAX_GESTURES):
        off = round((target - slider.value) / slider.step)
        if clicked and moved and off == 0:
            return
        pressed = not clicked or abs(off) > KEY_STEPS
        if pressed:
            x = min(max(x, rect.x + 1), rect.x + rect.width - 1)
            yield click(Point(x=x, y=rect.y + rect.height / 2))
            clicked = True
        else:
            # Level with the target but maybe unannounced: step away, and back on the next turn.
            up = off > 0 or (off == 0 and slider.value < slider.max)
            yield PrimitiveAction(api="key", args={"key": "ArrowRight" if up else "ArrowLeft"})
        after = await _slider(page, index)
        moved, slider = after.value != slider.value, after
        if pressed:  # a next click is aimed relative to where this one landed: the model's error cancels out
            x += (target - slider.value) / span * travel
    raise OracleDivergenceError(f"{what}: the {SLIDER_NAMES[index]} slider stays at {slider.value}, not {target}")


async def _eyedrop(page: Page, colour: str, eyedropper: Rect | None, what: str) -> AsyncIterator[PrimitiveAction]:
    """No slider setting gives ``colour``: the eyedropper picks it from the stage, where it is shown."""
    pixel = await page.stage_pixel(colour)
    if eyedropper is None or not pixel.found or pixel.point is None:
        raise OracleDivergenceError(
            f"{what}: no position of the colour picker's sliders gives {colour}, and the stage does not show it"
        )
    yield click(eyedropper.centre())
    await page.wait("quiet", what="the eyedropper to start")
    yield click(pixel.point)
    await page.wait("quiet", what="the eyedropper to pick")


async def _slider(page: Page, index: int) -> ColourSlider:
    picker = await page.colour_picker()
    if not picker.open or len(picker.sliders) != len(SLIDER_NAMES):
        raise OracleDivergenceError(f"the colour picker closed or changed ({len(picker.sliders)} sliders)")
    return picker.sliders[index]
