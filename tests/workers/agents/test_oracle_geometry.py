"""The primitive oracle's typed page reads, without a browser: replies in the page's shape validate,
and a reply in another shape stops the oracle with a one-line reason, never a pydantic traceback."""

from __future__ import annotations

import json
from typing import Any

import pytest
from pydantic import JsonValue

from workers.agents._primitive_oracle import OracleDivergenceError
from workers.agents._primitive_oracle._divergence import describe_difference
from workers.agents._primitive_oracle._geometry import FlyoutBlock, PaletteMiss
from workers.agents._primitive_oracle._page import Page
from workers.agents._primitive_oracle._state import ProjectSnapshot

RECT = {"x": 10, "y": 20, "width": 100, "height": 40}


class FakeEditor:
    """Answers every bridge call with one canned reply."""

    def __init__(self, reply: JsonValue) -> None:
        self.reply = reply

    async def call(self, name: str, args: dict[str, Any] | None = None) -> JsonValue:
        return self.reply


def page(reply: JsonValue) -> Page:
    return Page(FakeEditor(reply))  # type: ignore[arg-type]


async def test_palette_replies_are_told_apart_by_found() -> None:
    found = {
        "found": True,
        "id": "b",
        "rect": RECT,
        "visible": True,
        "grab": {"x": 73, "y": 128},
        "flyout": RECT,
        "flyoutScale": 0.675,
        "workspaceScale": 0.675,
    }
    block = await page(found).flyout_block("motion_movesteps", None)
    assert isinstance(block, FlyoutBlock)
    assert block.usable
    assert block.rect.centre().x == 60
    missing = await page({"found": False, "count": 0, "flyout": RECT}).flyout_block("motion_movesteps", None)
    assert isinstance(missing, PaletteMiss)


@pytest.mark.parametrize(
    ("reply", "reason"),
    [
        (None, "geometryLayout answered a reply the oracle cannot use: reply: Input should be"),
        ({"workspace": RECT}, "safeArea: Field required; overlays: Field required; flyout: Field required (+"),
    ],
)
async def test_a_reply_of_another_shape_is_a_one_line_divergence(reply: JsonValue, reason: str) -> None:
    with pytest.raises(OracleDivergenceError) as caught:
        await page(reply).layout()
    assert reason in str(caught.value)
    assert "\n" not in str(caught.value)
    assert caught.value.__cause__ is None and caught.value.__suppress_context__


async def test_a_union_reply_names_its_branch() -> None:
    with pytest.raises(OracleDivergenceError, match=r"found\.id: Field required"):
        await page({"found": True, "flyout": RECT}).flyout_block("motion_movesteps", None)
    with pytest.raises(OracleDivergenceError, match="not an object with found true or false"):
        await page({"found": 1}).flyout_button("Make a Variable")
    with pytest.raises(OracleDivergenceError, match="the prompt closed"):
        await page({"open": False}).modal()


def test_a_difference_is_described_by_target_and_script() -> None:
    script = [{"opcode": "event_whenflagclicked", "shadow": False, "fields": {}, "inputs": {}}]
    cat = {"name": "Cat", "isStage": False, "variables": ["variable:score"], "scripts": [json.dumps(script)]}
    expected = ProjectSnapshot.model_validate({"editingTarget": "Cat", "targets": [cat]})
    actual = {"editingTarget": "Cat", "targets": [{**cat, "variables": [], "scripts": []}]}
    assert describe_difference(expected, actual) == (
        "Cat variables [], expected ['variable:score']; Cat lacks script event_whenflagclicked"
    )
    assert describe_difference(expected, None) == "no snapshot could be read (got None)"
