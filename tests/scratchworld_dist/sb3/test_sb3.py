"""The project builder and the .sb3 pre-check (no browser)."""

from __future__ import annotations

import io
import json
import zipfile

import pytest

from scratchworld_dist import ProjectFormatError, ProjectTooLargeError
from scratchworld_dist.sb3 import Project, block, check_project, circle_costume, variable
from tests.support.projects import counter_project, with_declared_size, with_entry
from workers.contract import MIB, ProjectLimits


def test_builder_is_deterministic_and_round_trips() -> None:
    first, second = counter_project().to_sb3(), counter_project().to_sb3()
    assert first == second
    project = check_project(first)
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
def test_check_project_names_the_problem(data: bytes, message: str) -> None:
    with pytest.raises(ProjectFormatError, match=message):
        check_project(data)


def test_check_project_accepts_bare_project_json() -> None:
    raw = json.dumps(counter_project().to_project_json()).encode()
    assert check_project(raw)["targets"][0]["name"] == "Stage"


# --- size limits: checked before a browser sees the bytes ----------------------------------------

SMALL = ProjectLimits(max_file_mb=4, max_json_mb=0.5, max_entry_mb=1, max_total_mb=3, max_entries=20)


def test_real_projects_pass_the_default_limits() -> None:
    sb3 = with_entry(counter_project().to_sb3(), "sound.wav", bytes(5 * MIB))
    assert check_project(sb3)["targets"][0]["name"] == "Stage"


@pytest.mark.parametrize(
    ("build", "message"),
    [
        (
            lambda sb3: with_entry(sb3, "costume.svg", bytes(3 * MIB)),
            r"'costume.svg' is 3.00 MiB, over the limit of 1 MiB \(project_limits.max_entry_mb\)",
        ),
        (
            lambda sb3: with_entry(sb3, "extra.json", b" " * (3 * MIB // 2), level=9),
            r"'extra.json' is 1.50 MiB, over the limit of 1 MiB",
        ),
        (
            lambda sb3: with_declared_size(with_entry(sb3, "bomb.png", bytes(8 * MIB)), "bomb.png", 1000),
            r"'bomb.png' inflates past the limit of 1 MiB \(project_limits.max_entry_mb\)",
        ),
        (
            lambda sb3: with_entry(with_entry(with_entry(sb3, "a", bytes(MIB)), "b", bytes(MIB)), "c", bytes(MIB)),
            r"the inflated archive is 3.00 MiB, over the limit of 3 MiB \(project_limits.max_total_mb\)",
        ),
        (lambda sb3: sb3 + bytes(5 * MIB), r"the project file is 5.0\d MiB, over .*\(project_limits.max_file_mb\)"),
        (
            lambda sb3: _zip({"project.json": b'{"targets": [], "pad": "' + b"x" * MIB + b'"}'}),
            r"project.json is 1.00 MiB, over the limit of 0.5 MiB \(project_limits.max_json_mb\)",
        ),
        (
            lambda sb3: b'{"targets": [], "pad": "' + b"x" * MIB + b'"}',
            r"project.json is 1.00 MiB, over .*\(project_limits.max_json_mb\)",
        ),
        (lambda sb3: _zip({"project.json": b"{}", **{f"{n}.png": b"" for n in range(25)}}), "26 files.*max_entries"),
    ],
)
def test_projects_over_the_limits_are_refused_naming_the_limit(build: object, message: str) -> None:
    data = build(counter_project().to_sb3())  # type: ignore[operator]
    with pytest.raises(ProjectTooLargeError, match=message):
        check_project(data, SMALL)


def test_content_that_lies_about_its_size_or_checksum_is_refused() -> None:
    sb3 = with_entry(counter_project().to_sb3(), "costume.png", bytes(4000))
    with pytest.raises(ProjectFormatError, match="does not match the size or checksum"):
        check_project(with_declared_size(sb3, "costume.png", 1000))
    truncated = sb3[: zipfile.ZipFile(io.BytesIO(sb3)).getinfo("costume.png").header_offset + 40]
    with pytest.raises(ProjectFormatError):
        check_project(truncated + sb3[-200:])


def test_a_gigabyte_declared_asset_is_refused_from_its_header_under_the_defaults() -> None:
    sb3 = with_declared_size(with_entry(counter_project().to_sb3(), "huge.png", bytes(MIB)), "huge.png", 1536 * MIB)
    with pytest.raises(ProjectTooLargeError, match=r"'huge.png' is 1.50 GiB, over the limit of 64 MiB"):
        check_project(sb3)
