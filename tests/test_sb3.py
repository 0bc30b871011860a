"""The project builder and the .sb3 pre-check (no browser)."""

from __future__ import annotations

import io
import json
import zipfile

import pytest

from scratchworld_dist import ProjectFormatError
from scratchworld_dist.sb3 import Project, block, circle_costume, read_project_json, variable
from tests.projects import counter_project


def test_builder_is_deterministic_and_round_trips() -> None:
    first, second = counter_project().to_sb3(), counter_project().to_sb3()
    assert first == second
    project = read_project_json(first)
    stage, sprite = project["targets"]
    assert stage["isStage"] and stage["variables"] == {"variable-Stage-count": ["count", 0]}
    opcodes = sorted(b["opcode"] for b in sprite["blocks"].values())
    assert opcodes == sorted(
        ["event_whenflagclicked", "data_setvariableto", "control_repeat", "data_changevariableby", "looks_say"]
    )
    with zipfile.ZipFile(io.BytesIO(first)) as archive:
        costume = sprite["costumes"][0]
        assert costume["md5ext"] in archive.namelist()


def test_builder_links_stacks_and_reporters() -> None:
    project = Project()
    sprite = project.sprite("S", costume=circle_costume("c", 5, "#000")).variable("v", 3)
    sprite.script(
        block("event_whenflagclicked"),
        block("control_forever", SUBSTACK=[block("motion_movesteps", STEPS=variable("v"))]),
    )
    blocks = project.to_project_json()["targets"][1]["blocks"]
    hat = next(b for b in blocks.values() if b["opcode"] == "event_whenflagclicked")
    forever = blocks[hat["next"]]
    move = blocks[forever["inputs"]["SUBSTACK"][1]]
    assert move["parent"] == hat["next"]
    assert move["inputs"]["STEPS"] == [3, [12, "v", "variable-S-v"], [4, ""]]


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (lambda: block("motion_fly"), "unknown opcode"),
        (lambda: block("motion_movesteps", STEPZ=1), "has no slot"),
        (lambda: block("motion_gotoxy", X=1), "needs a value"),
        (lambda: block("control_if", CONDITION=3), "boolean block"),
    ],
)
def test_builder_rejects_bad_blocks(make, message) -> None:
    def build() -> bytes:
        project = Project()
        project.sprite("S", costume=circle_costume("c", 5, "#000")).script(block("event_whenflagclicked"), make())
        return project.to_sb3()

    with pytest.raises(ValueError, match=message):
        build()


def test_builder_rejects_unknown_variable() -> None:
    project = Project()
    project.sprite("S", costume=circle_costume("c", 5, "#000")).script(
        block("event_whenflagclicked"), block("data_setvariableto", VARIABLE="nope", VALUE=1)
    )
    with pytest.raises(ValueError, match="no variable named 'nope'"):
        project.to_sb3()


def _zip(files: dict[str, bytes]) -> bytes:
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w") as archive:
        for name, data in files.items():
            archive.writestr(name, data)
    return buffer.getvalue()


@pytest.mark.parametrize(
    ("data", "message"),
    [
        (b"", "empty"),
        (b"\x89PNG\r\n\x1a\n....", "not an .sb3 zip archive nor project JSON"),
        (counter_project().to_sb3()[:200], "not a readable zip archive"),
        (_zip({"sprite.json": b"{}"}), "no project.json"),
        (_zip({"project.json": b"{not json"}), "not valid JSON"),
        (_zip({"project.json": json.dumps({"targets": "none"}).encode()}), "no list of targets"),
        (b'{"objName": "Stage"}', "no list of targets"),
    ],
)
def test_read_project_json_names_the_problem(data: bytes, message: str) -> None:
    with pytest.raises(ProjectFormatError, match=message):
        read_project_json(data)


def test_read_project_json_accepts_bare_project_json() -> None:
    raw = json.dumps(counter_project().to_project_json()).encode()
    assert read_project_json(raw)["targets"][0]["name"] == "Stage"
