"""The catalog's perception-suite inputs: what `perception make` and `perception validate` refuse before a browser
starts. Tables of cases for ``tests/scratchworld_dist/cli/test_bad_inputs.py``, built with the helpers of
``tests/support/bad_inputs.py``."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

from tests.support.bad_inputs import GOLDEN, SUITE_DIR, CliCase, _args, _write

PERCEPTION_ITEMS = SUITE_DIR.parent / "perception-items"


def _put(path: Path, data: str | bytes) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    return _write(path, data)


def _make_from(data: bytes) -> Callable[[Path], tuple[list[str], list[str]]]:
    def build(tmp: Path) -> tuple[list[str], list[str]]:
        path = _write(tmp / "bad project.sb3", data)
        return ["perception", "make", str(GOLDEN), str(path), "--out", str(tmp / "out")], [str(path)]

    return build


def _make_into_full_folder(tmp: Path) -> tuple[list[str], list[str]]:
    _put(tmp / "out" / "notes.txt", "mine")
    return ["perception", "make", str(GOLDEN), "--out", str(tmp / "out")], [str(tmp / "out")]


def _upstream_perception(tmp: Path) -> tuple[list[str], list[str]]:
    """A clone's visual perception benchmark, one item: it has no facts, so nothing to re-derive."""
    root = tmp / "clone" / "visual_perception_benchmark"
    task = {"task_id": "1", "instruction": "Is there a `move` block?", "screenshot": "001.png",
            "task_type": "existence", "tag": "existence_yes_clear", "ground_truth": "YES"}  # fmt: skip
    _put(root / "tasks" / "1.json", json.dumps(task))
    _put(root / "screenshots_final" / "001.png", b"\x89PNG\r\n\x1a\n")
    return ["perception", "validate", str(tmp / "clone")], [str(tmp / "clone")]


PERCEPTION_CASES = [
    CliCase("make-from-a-text-file", _make_from(b"hello, I am a text file"), 2, "not a usable Scratch 3 project"),
    CliCase("make-from-a-corrupt-zip", _make_from(b"PK\x03\x04" + bytes(100)), 2, "not a usable Scratch 3 project"),
    CliCase("make-into-a-full-folder", _make_into_full_folder, 2, "folder that is not empty"),
    CliCase(
        "validate-an-upstream-suite", _upstream_perception, 2, "not a suite made by `scratchworld perception make`"
    ),
    CliCase(
        "validate-a-plain-folder",
        lambda tmp: (["perception", "validate", str(tmp)], [str(tmp)]),
        2,
        "not a perception suite",
    ),
    CliCase(
        "validate-an-unknown-view",
        _args("perception", "validate", str(PERCEPTION_ITEMS), "--views", "no_such_view", culprit="no_such_view"),
        2,
        "no view",
    ),
]
