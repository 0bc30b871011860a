"""Drag tasks in our format: written and read back, bad task files named on one line while the others still
load, the model's rules, and the editor layout's hit tests (upstream's layout: test_drag_tasks_upstream.py)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest
from pydantic import ValidationError

from scratchworld_dist import SuiteError
from scratchworld_dist.kinds.drag.items import (
    PALETTE_CATEGORIES,
    CanvasSource,
    DragSuite,
    DragTask,
    DragView,
    ExpectedConnection,
    FlyoutSource,
    load_drag_suite,
    write_drag_suite,
)
from scratchworld_dist.kinds.drag.items._layout import category_at, on_stage_selector, sprite_tile_at
from tests.support.drag_tasks import IDS, SB3, problems_of, without_project

# --- our own format ----------------------------------------------------------------------------


def _ours(tmp_path: Path) -> tuple[DragSuite, Path]:
    """A suite of ours written from three tasks: next, substack from the flyout, input."""
    project = tmp_path / "p.sb3"
    project.write_bytes(SB3)
    view = DragView(sprite="Dog", scroll_x=-10.5, scroll_y=3.0, scale=0.675)
    common: dict[str, Any] = {"instruction": "Drag it.", "initial_project": project}
    tasks = [
        DragTask(
            id="T1_a",
            type="T1",
            source=CanvasSource(
                block_id=IDS["Cat", "motion_turnright"],
                opcode="motion_turnright",
                tail_block_id=IDS["Cat", "motion_turnleft"],
            ),
            reference_block_id=IDS["Cat", "event_whenflagclicked"],
            reference_opcode="event_whenflagclicked",
            connection=ExpectedConnection(kind="next"),
            view=DragView(sprite="Cat", scroll_x=0, scroll_y=0, scale=1, stage_size="large", viewport=(1600, 900)),
            **common,
        ),
        DragTask(
            id="T2_b",
            type="T2",
            source=FlyoutSource(opcode="looks_hide"),
            reference_block_id=IDS["Dog", "control_forever"],
            reference_opcode="control_forever",
            connection=ExpectedConnection(kind="substack_1"),
            view=view.model_copy(update={"category": "looks", "flyout_scroll": 40.0}),
            **common,
        ),
        DragTask(
            id="T2_c",
            type="T2",
            source=FlyoutSource(opcode="data_variable"),
            reference_block_id=IDS["Dog", "motion_sety"],
            reference_opcode="motion_sety",
            connection=ExpectedConnection(kind="input", input_name="Y", variable_name="score"),
            view=view.model_copy(update={"category": "variables"}),
            **common,
        ),
    ]
    root = write_drag_suite(tasks, tmp_path / "suite", "mine")
    return DragSuite(name="mine", kind="scratchworld_dist", root=root, items=tuple(tasks)), root


def test_our_format_round_trip(tmp_path: Path) -> None:
    written, root = _ours(tmp_path)
    suite = load_drag_suite(root)
    assert suite.kind == "scratchworld_dist" and suite.name == "mine" and not suite.problems
    assert [without_project(t) for t in suite.tasks] == [without_project(t) for t in written.tasks]
    assert all(t.initial_project.read_bytes() == SB3 for t in suite.tasks)
    assert all(t.initial_project.is_relative_to(root) for t in suite.tasks)
    # Writing what was read gives the same files.
    write_drag_suite(suite.tasks, tmp_path / "again", "mine")
    for path in sorted(root.rglob("*.json")):
        assert path.read_text() == (tmp_path / "again" / path.relative_to(root)).read_text()


def test_write_refuses_incomplete_tasks_and_used_folders(tmp_path: Path) -> None:
    written, root = _ours(tmp_path)
    with pytest.raises(SuiteError, match="not empty"):
        write_drag_suite(written.tasks, root, "mine")
    no_view = written.tasks[0].model_copy(update={"view": None})
    with pytest.raises(SuiteError, match="task T1_a has no view"):
        write_drag_suite([no_view], tmp_path / "other", "mine")
    assert not (tmp_path / "other").exists()
    with pytest.raises(SuiteError, match="cannot name a drag suite"):
        write_drag_suite(written.tasks, tmp_path / "other", "two\nlines")


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (lambda t: t["connection"].update(kind="sideways"), "connection.kind: Input should be 'parent'"),
        (
            lambda t: t.update(initial_project="projects/absent.sb3"),
            "initial_project: 'projects/absent.sb3' does not exist",
        ),
        (lambda t: t.update(view=None), "view: required"),
        (
            lambda t: t["view"].update(sprite="Cat"),
            "view.sprite: the view shows sprite 'Cat' but the reference block is in sprite 'Dog'",
        ),
        (
            lambda t: t["view"].update(category="motion"),
            "view.category: the view selects 'motion' but looks_hide is in 'looks'",
        ),
        (lambda t: t.update(reference_opcode="control_if"), "reference_opcode: 'control_if', but the project's block"),
    ],
)
def test_bad_task_files_of_ours(tmp_path: Path, edit: Any, message: str) -> None:
    _, root = _ours(tmp_path)
    path = root / "tasks" / "T2_b.json"
    data = json.loads(path.read_text())
    edit(data)
    path.write_text(json.dumps(data))
    suite = load_drag_suite(root)
    assert [t.id for t in suite.tasks] == ["T1_a", "T2_c"]
    assert message in problems_of(suite, "T2_b")


def test_our_manifest_and_stray_files(tmp_path: Path) -> None:
    _, root = _ours(tmp_path)
    (root / "tasks" / "T2_b.json").write_text("{broken")
    (root / "tasks" / "extra.json").write_text("{}")
    suite = load_drag_suite(root)
    assert "malformed JSON" in problems_of(suite, "T2_b")
    assert any(str(p).endswith("extra.json: not listed in drag-suite.json; not loaded") for p in suite.problems)
    (root / "drag-suite.json").write_text(json.dumps({"format": "scratchworld_dist/drag/9", "name": "x", "tasks": []}))
    with pytest.raises(SuiteError, match="format"):
        load_drag_suite(root)


def test_model_rules() -> None:
    with pytest.raises(ValidationError, match="needs input_name"):
        ExpectedConnection(kind="input")
    with pytest.raises(ValidationError, match="not 'next'"):
        ExpectedConnection(kind="next", variable_name="x")
    with pytest.raises(ValidationError, match="set category too"):
        DragView(sprite=None, flyout_scroll=10, scroll_x=0, scroll_y=0, scale=1)
    base = {
        "id": "T1_x",
        "type": "T1",
        "instruction": "x",
        "initial_project": "p.sb3",
        "source": {"kind": "flyout", "opcode": "looks_hide"},
        "reference_block_id": "r",
        "reference_opcode": "looks_show",
        "connection": {"kind": "substack_1"},
        "view": {"sprite": "Cat", "scroll_x": 0, "scroll_y": 0, "scale": 1},
    }
    with pytest.raises(ValidationError, match="a T1 task connects by parent, next"):
        DragTask.model_validate(base)
    with pytest.raises(ValidationError, match=r"needs view\.category"):
        DragTask.model_validate({**base, "connection": {"kind": "next"}})
    with pytest.raises(ValidationError, match="not a plain name"):
        DragTask.model_validate({**base, "id": "a\nb"})


def test_layout_hit_tests() -> None:
    centres = [round(92 + 45 * (i + 0.5)) for i in range(len(PALETTE_CATEGORIES))]
    assert [category_at(31, y) for y in centres] == list(PALETTE_CATEGORIES)
    assert category_at(31, 92 + 45) is None  # on the border between two buttons
    assert category_at(70, 115) is None  # in the flyout
    assert [sprite_tile_at(x, y) for x, y in [(1071, 420), (1143, 420), (1071, 492), (1143, 564)]] == [0, 1, 2, 5]
    assert sprite_tile_at(1107, 420) is None and sprite_tile_at(1071, 636) is None  # a gap; under the add button
    assert on_stage_selector(1236, 501) and not on_stage_selector(1143, 420)
