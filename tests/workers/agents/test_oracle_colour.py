"""The primitive oracle's colour arithmetic, without a browser: slider settings on the picker's own
grids that give a colour exactly through Blockly's conversion, or none when no setting does."""

from __future__ import annotations

import pytest

from workers.agents._primitive_oracle._colour import grid, hsv_to_hex, rgb_to_hsv, slider_values
from workers.agents._primitive_oracle._geometry import ColourSlider, Rect

RECT = Rect(x=0, y=0, width=150, height=20)


def slider(maximum: float, step: float) -> ColourSlider:
    return ColourSlider(rect=RECT, value=0, min=0, max=maximum, step=step, focused=False)


SLIDERS = [slider(360, 1), slider(1, 0.001), slider(255, 1)]
"""The picker's sliders as Scratch draws them: hue 0-360, saturation 0-1 by 0.001, brightness 0-255."""


@pytest.mark.parametrize("colour", ["#1505ff", "#ff0000", "#123456", "#abcdef", "#0a0a0b", "#4d97ff"])
def test_a_colour_gets_slider_values_that_give_it_exactly(colour: str) -> None:
    values = slider_values(colour, SLIDERS)
    assert values is not None
    hue, saturation, brightness = values
    assert hue in grid(SLIDERS[0]) and saturation in grid(SLIDERS[1]) and brightness in grid(SLIDERS[2])
    assert hsv_to_hex(hue, saturation, brightness) == colour


def test_the_setting_nearest_the_colours_own_hsv_is_chosen() -> None:
    # rgbToHsv(#1505ff) is (243.84, 0.9804, 255): hue 243 gives #1705ff, hue 244 with saturation 0.98 gives it.
    assert rgb_to_hsv(0x15, 0x05, 0xFF) == pytest.approx((243.84, 250 / 255, 255.0))
    assert slider_values("#1505ff", SLIDERS) == (244, 0.98, 255)


def test_greys_need_no_saturation_and_unreachable_colours_are_none() -> None:
    assert slider_values("#000000", SLIDERS) == (0, 0.0, 0.0)
    assert slider_values("#7f7f7f", SLIDERS) == (0, 0.0, 127.0)
    assert slider_values("#00ff01", SLIDERS) is None  # no hue step puts 1 in blue under a full green
    assert slider_values("#ffab19", SLIDERS) is None  # Scratch's own orange: no whole hue gives 0xab
    assert slider_values("#fff700", SLIDERS) is None  # (the oracle picks such a colour from the stage)
    assert slider_values("red", SLIDERS) is None


def test_saturation_steps_are_the_numbers_the_input_reports() -> None:
    steps = grid(SLIDERS[1])
    assert len(steps) == 1001
    assert steps[9] == float("0.009")  # k/1000 parses as the range input's text does; 9 * 0.001 does not
    assert float("0.009") != 9 * 0.001
