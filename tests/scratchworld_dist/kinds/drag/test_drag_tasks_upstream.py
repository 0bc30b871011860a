"""Drag tasks in upstream's layout: a small clone built here, mapped to views from its pre-actions, every bad
input named on one line while the other tasks still load; and upstream's own 60 tasks."""

from __future__ import annotations

import json
from collections import Counter
from pathlib import Path
from typing import Any

import pytest

from scratchworld_dist import SuiteError
from scratchworld_dist.kinds.drag.items import (
    CanvasSource,
    DragView,
    ExpectedConnection,
    FlyoutSource,
    load_drag_suite,
    write_drag_suite,
)
from scratchworld_dist.kinds.drag.items._layout import FLYOUT
from tests.support.drag_tasks import IDS, SB3, problems_of, without_project

# --- a small clone in upstream's layout, built here -----------------------------------------

WORKSPACE = {"tx": 100.0, "ty": -50.0, "scale": 0.5, "scrollX": -200.0, "scrollY": 100.0}
TILE_2 = {"api": "click", "args": {"x": 1143, "y": 420}}  # the second sprite tile
STAGE = {"api": "click", "args": {"x": 1236, "y": 501}}
MOTION = {"api": "click", "args": {"x": 31, "y": 115}}


def _task(task_id: str = "T1_001", **changes: Any) -> dict[str, Any]:
    """An upstream task file: by default, drag Cat's free stack below its green-flag script."""
    config: dict[str, Any] = {
        "target_block_opcode": "motion_turnright",
        "target_block_id": IDS["Cat", "motion_turnright"],
        "target_stack_tail_block_id": IDS["Cat", "motion_turnleft"],
        "reference_block_id": IDS["Cat", "motion_movesteps"],
        "reference_block_opcode": "motion_movesteps",
        "connection_type": "next",
        "target_input_name": None,
        "description": "note",
        "workspace_state": WORKSPACE,
        "drag_start_point": [400, 300],
        "feasible_start_points": [[400, 300], [405, 300], [400, 310]],
        "feasible_points": [[600, 200], [602, 200]],
    }
    top = {"id": task_id, "category": "T1", "instruction": "Drag it.", "init_project": "p.sb3"}
    for key, value in changes.items():
        (top if key in top or key == "sprite" else config)[key] = value
    return {**top, "evaluation_config": config}


def _clone(root: Path, *tasks: dict[str, Any]) -> Path:
    (root / "scratch-gui" / "static").mkdir(parents=True)
    (root / "scratch-gui" / "static" / "p.sb3").write_bytes(SB3)
    folder = root / "single_step_drag_benchmark" / "tasks"
    folder.mkdir(parents=True)
    for task in tasks:
        (folder / f"{task['id']}.json").write_text(json.dumps(task))
    return root


def test_a_clean_upstream_task(tmp_path: Path) -> None:
    suite = load_drag_suite(_clone(tmp_path, _task()))
    assert suite.kind == "upstream" and not suite.problems
    task = suite.task("T1_001")
    assert task.source == CanvasSource(
        block_id=IDS["Cat", "motion_turnright"], opcode="motion_turnright", tail_block_id=IDS["Cat", "motion_turnleft"]
    )
    assert task.connection == ExpectedConnection(kind="next")
    # No switch: the editor shows the first sprite; the scroll is the recorded transform's.
    assert task.view == DragView(sprite="Cat", scroll_x=-200.0, scroll_y=100.0, scale=0.5)
    assert task.upstream is not None
    assert task.upstream.start_grid_step == 5 and task.upstream.end_grid_step == 2
    assert task.initial_project == tmp_path / "scratch-gui" / "static" / "p.sb3"


@pytest.mark.parametrize(
    ("click", "sprite"),
    [((1071, 420), "Cat"), ((1143, 420), "Dog"), ((1071, 492), "Bird"), ((1236, 501), None)],
)
def test_sprite_clicks_select_tiles_in_project_order(
    tmp_path: Path, click: tuple[int, int], sprite: str | None
) -> None:
    owner = sprite or "Stage"
    opcode = "control_wait" if owner == "Stage" else "event_whenflagclicked"
    task = _task(
        reference_block_id=IDS[owner, opcode],
        reference_block_opcode=opcode,
        target_block_id=None,
        target_stack_tail_block_id=None,
        target_block_opcode="motion_movesteps",
        use_flyout=True,
        switch_sprite_actions=[{"api": "click", "args": {"x": click[0], "y": click[1]}}],
        locate_target_actions=[
            MOTION,
            {"api": "scroll", "args": {"direction": "down", "amount": 120, "x": 186, "y": 390}},
        ],
    )
    view = load_drag_suite(_clone(tmp_path, task)).task("T1_001").view
    assert view is not None
    assert (view.sprite, view.category, view.flyout_scroll) == (sprite, "motion", 120)


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        (
            {"switch_sprite_actions": [{"api": "click", "args": {"x": 1000, "y": 300}}]},
            "switch_sprite_actions[0]: click (1000, 300) is on no",
        ),
        (
            {"switch_sprite_actions": [{"api": "click", "args": {"x": 1143, "y": 492}}]},
            "sprite tile 4, the project has 3",
        ),
        (
            {"switch_sprite_actions": [{"api": "click", "args": {"x": 1107, "y": 420}}]},
            "is on no category button",
        ),  # between tiles
        (
            {"locate_target_actions": [{"api": "click", "args": {"x": 31, "y": 137}}]},
            "locate_target_actions[0]: click (31, 137)",
        ),
        ({"locate_target_actions": [{"api": "scroll", "args": {"x": 186, "y": 390}}]}, "before any category click"),
        (
            {"locate_target_actions": [{"api": "double_click", "args": {"x": 31, "y": 115}}]},
            "'double_click' is not a click",
        ),
        ({"pan_canvas_actions": [{"api": "custom_js", "args": {"fn": "() => 1"}}]}, "not upstream's pan script"),
        ({"workspace_state": None}, "workspace_state: missing"),
        ({"workspace_state": {**WORKSPACE, "scrollX": 5.0}}, "scrollX 5 is not -translate/scale (-200)"),
        ({"sprite": "dog"}, "sprite: upstream names 'dog' but its clicks select sprite 'Cat'"),
        ({"switch_sprite_actions": [TILE_2]}, "the view shows sprite 'Dog' but the reference block is in sprite 'Cat'"),
        ({"switch_sprite_actions": [STAGE]}, "the view shows the Stage but the reference block"),
    ],
)
def test_unmappable_pre_actions_keep_the_task_without_a_view(
    tmp_path: Path, changes: dict[str, Any], message: str
) -> None:
    suite = load_drag_suite(_clone(tmp_path, _task(**changes), _task("T1_002")))
    assert suite.task("T1_001").view is None
    assert suite.task("T1_002").view is not None
    assert message in problems_of(suite, "T1_001")
    assert {p.effect for p in suite.problems} == {"no_view"}
    assert [t.id for t in suite.ready] == ["T1_002"]


def test_a_flyout_source_from_another_category_is_not_a_view(tmp_path: Path) -> None:
    task = _task(
        target_block_id=None, target_stack_tail_block_id=None, use_flyout=True, target_block_opcode="looks_hide"
    )
    task["evaluation_config"]["locate_target_actions"] = [MOTION]
    suite = load_drag_suite(_clone(tmp_path, task))
    assert "the view selects 'motion' but looks_hide is in 'looks'" in problems_of(suite, "T1_001")


def test_wrong_opcode_labels_are_corrected_from_the_project(tmp_path: Path) -> None:
    suite = load_drag_suite(_clone(tmp_path, _task(reference_block_opcode="motion_setx")))
    task = suite.task("T1_001")
    assert task.reference_opcode == "motion_movesteps" and task.view is not None
    assert "reference_block_opcode: 'motion_setx', but the project's block" in problems_of(suite, "T1_001")
    assert suite.problems[0].effect == "corrected"


@pytest.mark.parametrize(
    ("task", "message"),
    [
        (_task(connection_type="sideways"), "evaluation_config.connection_type: Input should be 'parent', 'next'"),
        (_task(connection_type="input"), "'input' is not a T1 connection (parent, next)"),
        (_task(category="T2", connection_type="input"), "target_input_name: connection_type 'input' needs"),
        (_task(target_input_name="VALUE"), "target_input_name: only for connection_type 'input', not 'next'"),
        (_task(init_project="absent.sb3"), "init_project: 'absent.sb3' does not exist"),
        (_task(init_project="../p.sb3"), "init_project: '../p.sb3' is outside"),
        (_task(use_flyout=True), "use_flyout: must be true exactly when target_block_id is null"),
        (_task(reference_block_id="nope"), "reference_block_id: 'nope' is not a block of the project"),
        (_task(target_stack_tail_block_id=IDS["Cat", "motion_turnright"]), "target_stack_tail_block_id:"),
        (_task(id="T9_999"), "id: 'T9_999' differs from the file name 'T1_001'"),
        ({**_task(), "instruction": ""}, "instruction: String should have at least 1 character"),
    ],
)
def test_bad_upstream_tasks_are_skipped_and_named(tmp_path: Path, task: dict[str, Any], message: str) -> None:
    root = _clone(tmp_path, _task("T1_002"))
    (root / "single_step_drag_benchmark" / "tasks" / "T1_001.json").write_text(json.dumps(task))
    suite = load_drag_suite(root)
    assert [t.id for t in suite.tasks] == ["T1_002"]
    assert message in problems_of(suite, "T1_001")
    assert suite.problems[0].effect == "skipped"


def test_malformed_and_unreadable_files(tmp_path: Path) -> None:
    root = _clone(tmp_path, _task("T1_002"))
    (root / "single_step_drag_benchmark" / "tasks" / "T1_001.json").write_text("{broken")
    (root / "scratch-gui" / "static" / "bad.sb3").write_bytes(b"not a zip")
    (root / "single_step_drag_benchmark" / "tasks" / "T1_003.json").write_text(
        json.dumps(_task("T1_003", init_project="bad.sb3"))
    )
    suite = load_drag_suite(root)
    assert [t.id for t in suite.tasks] == ["T1_002"]
    assert "malformed JSON" in problems_of(suite, "T1_001")
    assert "init_project:" in problems_of(suite, "T1_003") and "not a usable project" in problems_of(suite, "T1_003")
    with pytest.raises(SuiteError, match="2 problems in the suite"):
        suite.raise_for_problems()


def test_not_a_drag_suite(tmp_path: Path) -> None:
    with pytest.raises(SuiteError, match="not a drag suite"):
        load_drag_suite(tmp_path)
    with pytest.raises(SuiteError, match="no such directory"):
        load_drag_suite(tmp_path / "absent")


# --- upstream's 60 tasks -----------------------------------------------------------------------


@pytest.fixture
def drag_upstream(upstream_dir: Path) -> Path:
    if not (upstream_dir / "single_step_drag_benchmark" / "tasks").is_dir():
        pytest.skip(f"no single_step_drag_benchmark in {upstream_dir}")
    return upstream_dir


def _upstream_json(root: Path, task_id: str) -> dict[str, Any]:
    return json.loads((root / "single_step_drag_benchmark" / "tasks" / f"{task_id}.json").read_text())


@pytest.mark.upstream
def test_all_60_upstream_tasks_load_with_views(drag_upstream: Path) -> None:
    suite = load_drag_suite(drag_upstream)
    assert suite.kind == "upstream"
    assert Counter(t.type for t in suite.tasks) == {"T1": 30, "T2": 30}
    assert len(suite.ready) == 60
    assert {p.effect for p in suite.problems} <= {"corrected"}
    # Loading from the benchmark's own folder finds the clone.
    assert len(load_drag_suite(drag_upstream / "single_step_drag_benchmark" / "tasks").tasks) == 60
    for task in suite.tasks:
        config = _upstream_json(drag_upstream, task.id)["evaluation_config"]
        assert task.view is not None and task.upstream is not None
        assert (task.view.scroll_x, task.view.scale) == (
            config["workspace_state"]["scrollX"],
            config["workspace_state"]["scale"],
        )
        assert task.connection.kind == config["connection_type"]
        assert isinstance(task.source, FlyoutSource) == bool(config.get("use_flyout"))
        assert task.upstream.drag_start_point == tuple(config["drag_start_point"])


@pytest.mark.upstream
def test_upstream_fields_of_known_tasks(drag_upstream: Path) -> None:
    suite = load_drag_suite(drag_upstream)
    t1_parent = suite.task("T1_001")
    assert t1_parent.connection.kind == "parent"
    assert t1_parent.source == CanvasSource(
        block_id="/dLn8c[CHgg=NxAN)1Kn", opcode="event_whenflagclicked", tail_block_id="/dLn8c[CHgg=NxAN)1Kn"
    )
    assert (t1_parent.reference_block_id, t1_parent.reference_opcode) == (
        "}qOAjx@6:8y_k(fXnJ^U",
        "motion_setrotationstyle",
    )
    assert t1_parent.view == DragView(
        sprite="Sprite1", scroll_x=-224.52544487847223, scroll_y=63.69443540219907, scale=0.675
    )

    t1_next = suite.task("T1_013")  # a flyout block into the Stage's script
    assert t1_next.connection.kind == "next" and t1_next.source == FlyoutSource(opcode="data_setvariableto")
    assert t1_next.view is not None and (t1_next.view.sprite, t1_next.view.category) == (None, "variables")

    stack = suite.task("T1_006")  # a stack: the tail is not the block dragged
    assert isinstance(stack.source, CanvasSource) and stack.source.tail_block_id != stack.source.block_id

    substack = suite.task("T2_002")
    assert substack.connection.kind == "substack_1" and substack.source == FlyoutSource(opcode="motion_movesteps")
    assert substack.view is not None and substack.view.category == "motion"
    assert suite.task("T2_001").connection.kind == "substack_2"

    variable = suite.task("T2_025")  # the second sprite's tile, a variable from the flyout
    assert variable.connection == ExpectedConnection(kind="input", input_name="OPERAND1", variable_name="currentLevel")
    assert variable.view is not None and (variable.view.sprite, variable.view.category) == ("Goal", "variables")
    assert suite.task("T2_017").connection == ExpectedConnection(
        kind="input", input_name="STRING", variable_name="number"
    )

    third = suite.task("T1_030")  # the third sprite's tile
    assert third.view is not None and third.view.sprite == "Power Up"
    scrolled = suite.task("T1_004")
    assert scrolled.view is not None and (scrolled.view.category, scrolled.view.flyout_scroll) == ("motion", 120)

    corrected = suite.task("T1_011")  # upstream labels the reference 'event_whenbroadcastreceived'
    assert corrected.reference_opcode == "event_broadcast"
    assert t1_parent.upstream is not None and t1_parent.upstream.start_grid_step == 5
    reference = suite.task("T2_017").upstream  # input tasks: ends sampled on one row, 2 px apart
    assert reference is not None and reference.end_grid_step == 2


@pytest.mark.upstream
def test_upstream_starts_agree_with_the_deduced_flyout_edge(drag_upstream: Path) -> None:
    """Every flyout drag starts in the flyout, every canvas drag to its right: the 310 px edge holds."""
    for task in load_drag_suite(drag_upstream).tasks:
        assert task.upstream is not None
        x, y = task.upstream.drag_start_point
        assert FLYOUT.contains(x, y) == isinstance(task.source, FlyoutSource), task.id


@pytest.mark.upstream
def test_upstream_round_trips_through_our_format(drag_upstream: Path, tmp_path: Path) -> None:
    upstream = load_drag_suite(drag_upstream)
    ours = load_drag_suite(write_drag_suite(upstream.tasks, tmp_path / "drag", "upstream-copy"))
    assert not ours.problems
    assert [without_project(t) for t in ours.tasks] == [without_project(t) for t in upstream.tasks]
    for mine, theirs in zip(ours.tasks, upstream.tasks, strict=True):
        assert mine.initial_project.read_bytes() == theirs.initial_project.read_bytes()
