"""The project builder writes pen blocks, and lists the pen extension exactly when a project uses it."""

from __future__ import annotations

import pytest

from scratchworld_dist.sb3 import Block, Project, block, circle_costume


def project(*script: Block) -> Project:
    built = Project()
    built.sprite("Cat", costume=circle_costume("a", 10, "#36c")).script(block("event_whenflagclicked"), *script)
    return built


def test_a_project_with_pen_blocks_lists_the_pen_extension() -> None:
    data = project(block("pen_setPenColorToColor", COLOR="#ff0000"), block("pen_penDown"), block("pen_stamp"))
    written = data.to_project_json()
    assert written["extensions"] == ["pen"]
    blocks = written["targets"][1]["blocks"]
    colour = next(b for b in blocks.values() if b["opcode"] == "pen_setPenColorToColor")
    assert colour["inputs"]["COLOR"] == [1, [9, "#ff0000"]]


def test_a_project_without_them_lists_none() -> None:
    assert project(block("motion_movesteps", STEPS=10)).to_project_json()["extensions"] == []


def test_a_pen_block_with_a_misspelt_slot_is_refused() -> None:
    with pytest.raises(ValueError, match="pen_setPenSizeTo has no slot"):
        block("pen_setPenSizeTo", WIDTH=3)
