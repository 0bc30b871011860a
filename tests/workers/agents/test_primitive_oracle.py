"""The golden trajectories in a real editor: replayed through the composite API, and performed by the
primitive oracle through gestures alone; its drags snap where planned (and nowhere when aimed at
empty space), and its self-check stops a gesture gone astray."""

from __future__ import annotations

import io
import json
import zipfile

import pytest

from scratchworld_dist.sb3 import Project, block, circle_costume
from scratchworld_dist.suites import load_suite
from tests.conftest import SUITE_DIR, pooled_editor, primitive_editor
from tests.support.primitive_oracle import Run, Tamper, composite_and_oracle, drive, sprite_block_ids
from workers import composite
from workers.agents._primitive_oracle import OracleDivergenceError, PrimitiveOracle
from workers.agents._primitive_oracle._page import Page
from workers.agents._primitive_oracle._scrolling import wheel_point
from workers.contract import CompositeAction, EvalResult, PrimitiveAction
from workers.editor import Editor, EditorPool
from workers.evaluation import Evaluator
from workers.primitive import Gestures

pytestmark = pytest.mark.browser

ALL_TASKS = sorted(p.parent.name for p in SUITE_DIR.glob("*/*/golden_trajectory.json"))


def cat_project() -> Project:
    """Cat: when flag clicked, move 10, turn 15, say "hi"; a forever loop holding one change x."""
    project = Project()
    cat = project.sprite("Cat", costume=circle_costume("cat", 10, "#f80"))
    cat.script(
        block("event_whenflagclicked"),
        block("motion_movesteps", STEPS=10),
        block("motion_turnright", DEGREES=15),
        block("looks_say", MESSAGE="hi"),
    )
    cat.script(block("control_forever", SUBSTACK=[block("motion_changexby", DX=1)]))
    return project


async def solve(
    shared_pool: EditorPool, evaluator: Evaluator, task_id: str, tamper: Tamper | None = None
) -> tuple[Run, EvalResult]:
    task = load_suite(SUITE_DIR).task(task_id)
    initial = task.initial_project.read_bytes()
    async with primitive_editor(shared_pool, initial) as editor:
        oracle = PrimitiveOracle(initial, task.trajectory() or [])
        await oracle.begin(editor)
        run = await drive(editor, oracle, tamper)
        assert oracle.gesture_count == run.gestures
        project = await editor.save_project()
    return run, await evaluator.evaluate(project, task.evaluation_spec())


@pytest.mark.parametrize("task_id", ALL_TASKS)
@pytest.mark.slow
async def test_each_golden_trajectory_solves_its_task_in_both_modes(
    shared_pool: EditorPool, evaluator: Evaluator, task_id: str
) -> None:
    """The trajectory replayed through the composite API, then performed by the oracle as gestures in the
    same page (reloaded, as the oracle's own dry run leaves it): each saved project passes the task.

    (Once two tests, here and in the composite tests, each opening an editor for the same trajectory.)
    """
    task = load_suite(SUITE_DIR).task(task_id)
    initial = task.initial_project.read_bytes()
    async with pooled_editor(shared_pool) as editor:
        await editor.load_project(initial)
        for action in task.trajectory() or []:
            envelope = await composite.execute(editor, action.api, action.args)
            assert envelope.success, (action, envelope.error)
        replayed = await editor.save_project()

        await editor.load_project(initial)
        await editor.set_stage_size("small")  # as primitive episodes get it
        oracle = PrimitiveOracle(initial, task.trajectory() or [])
        await oracle.begin(editor)
        run = await drive(editor, oracle)
        assert oracle.gesture_count == run.gestures
        performed = await editor.save_project()
    print(f"{task_id}: {run.gestures} gestures, {run.seconds:.1f} s")
    for mode, project in (("composite", replayed), ("primitive", performed)):
        result = await evaluator.evaluate(project, task.evaluation_spec())
        assert result.success, (mode, result.model_dump(include={"passed", "total", "tests", "error"}))
    assert run.gestures > 0
    # The real run only reads the page: no composite call, no VM write.
    assert run.calls
    assert all(name.startswith("geometry") for name in run.calls), sorted(set(run.calls))


def test_the_suite_has_every_task() -> None:
    assert len(ALL_TASKS) == 12


async def cat_ids(editor: Editor) -> dict[str, str]:
    """Block id by opcode (Cat's blocks have one of each)."""
    return await sprite_block_ids(editor, "Cat")


async def test_a_planned_drag_snaps_and_a_drop_in_free_space_does_not(shared_pool: EditorPool) -> None:
    async with primitive_editor(shared_pool, cat_project().to_sb3()) as editor:
        ids = await cat_ids(editor)
        gestures = Gestures(editor.page)
        # The forever loop goes under the say block: its top meets the say block's next connection.
        plan = await editor.call(
            "geometryPlanDrag",
            {"moving": ids["control_forever"], "local": "previous", "target": ids["looks_say"], "remote": "next"},
        )
        assert isinstance(plan, dict)
        assert plan["clean"], plan
        drag = {"start_x": plan["grab"]["x"], "start_y": plan["grab"]["y"]}
        envelope = await gestures.execute(
            "drag_and_drop", {**drag, "end_x": plan["end"]["x"], "end_y": plan["end"]["y"]}
        )
        assert envelope.success
        assert (await editor.call("geometryWait", {"until": "quiet"}))["ok"]  # type: ignore[index,call-overload]
        forever = await editor.call("geometryBlock", {"id": ids["control_forever"]})
        assert forever["attachment"] == {"parent": ids["looks_say"], "input": None}  # type: ignore[index,call-overload]

        # A move block from the palette, dropped at the free spot nearest to the script's end.
        palette = await editor.call("geometryFlyoutBlock", {"opcode": "motion_movesteps"})
        assert isinstance(palette, dict)
        assert palette["visible"]
        end = forever["lastNext"] or forever["rect"]  # type: ignore[index,call-overload]
        spot = (await editor.call("geometryFreeSpot", {"width": 120, "height": 40, "near": end}))["spot"]  # type: ignore[index,call-overload]
        assert abs(spot["y"] - end["y"]) < 150  # near the script, yet out of snapping reach
        grab = palette["grab"]
        offset = (grab["x"] - palette["rect"]["x"], grab["y"] - palette["rect"]["y"])
        before = await editor.call("geometrySnapshot")
        drop = {"end_x": spot["x"] + offset[0], "end_y": spot["y"] + offset[1]}
        assert (await gestures.execute("drag_and_drop", {"start_x": grab["x"], "start_y": grab["y"], **drop})).success
        tops = await editor.call(
            "geometryWait",
            {"until": "newBlock", "args": {"opcode": "motion_movesteps", "known": [ids["event_whenflagclicked"]]}},
        )
        assert isinstance(tops, dict)
        assert tops["ok"], tops  # one new top-level move block
        after = await editor.call("geometrySnapshot")
        scripts = lambda state: state["state"]["targets"][1]["scripts"]  # noqa: E731
        assert len(scripts(after)) == len(scripts(before)) + 1  # type: ignore[arg-type]
        assert set(scripts(before)) <= set(scripts(after))  # type: ignore[arg-type]


class DropInPlace:
    """Tamper: the first drag that starts in the workspace (a connecting drag) drops where it started."""

    def __init__(self) -> None:
        self.done = False

    def __call__(self, count: int, action: PrimitiveAction) -> PrimitiveAction:
        start_x, start_y = action.args.get("start_x"), action.args.get("start_y")
        if self.done or action.api != "drag_and_drop" or not isinstance(start_x, (int, float)) or start_x < 320:
            return action
        assert isinstance(start_y, (int, float))
        self.done = True
        return PrimitiveAction(api=action.api, args={**action.args, "end_x": start_x + 4, "end_y": start_y + 4})


async def test_the_self_check_stops_at_a_block_that_did_not_snap(shared_pool: EditorPool, evaluator: Evaluator) -> None:
    tamper = DropInPlace()
    with pytest.raises(
        OracleDivergenceError, match=r"after step \d+ connect_blocks .*differs from the composite dry run.*lacks script"
    ):
        await solve(shared_pool, evaluator, "quiz_score", tamper)
    assert tamper.done


async def test_the_self_check_stops_at_a_value_that_was_not_typed(
    shared_pool: EditorPool, evaluator: Evaluator
) -> None:
    def mistype(count: int, action: PrimitiveAction) -> PrimitiveAction:
        return PrimitiveAction(api="type", args={"text": "7"}) if action.api == "type" else action

    with pytest.raises(OracleDivergenceError, match=r"step 9 set_block_field .*typing 'Reset!' left \['7', '7', '7'\]"):
        await solve(shared_pool, evaluator, "click_counter_reset", mistype)


CAT_TRAJECTORY = [
    ("select_sprite", {"name": "Cat"}),
    ("add_block", {"blockType": "motion_gotoxy"}),
    ("connect_blocks", {"sourceBlockIndex": 7, "targetBlockIndex": 3, "placement": {"kind": "stack_before"}}),
    ("detach_blocks", {"blockIndex": 4}),
    ("add_block", {"blockType": "control_repeat"}),
    ("connect_blocks", {"sourceBlockIndex": 8, "targetBlockIndex": 6, "placement": {"kind": "wrap"}}),
    ("connect_blocks", {"sourceBlockIndex": 6, "targetBlockIndex": 3, "placement": {"kind": "stack_after"}}),
    ("delete_block", {"blockIndex": 8}),
    ("add_block", {"blockType": "looks_show"}),
    ("connect_blocks", {"sourceBlockIndex": 8, "targetBlockIndex": 7, "placement": {"kind": "stack_before"}}),
]
"""Insert before a middle block, detach, wrap, stack after, delete, and put a block on top of a script."""


async def test_detach_delete_wrap_and_stack_before_end_as_in_composite_mode(shared_pool: EditorPool) -> None:
    trajectory = [CompositeAction(api=api, args=args) for api, args in CAT_TRAJECTORY]
    expected, performed, run = await composite_and_oracle(shared_pool, cat_project().to_sb3(), trajectory)
    assert "looks_show" in expected
    assert performed == expected
    assert run.gestures >= 10


async def test_a_trajectory_that_fails_in_composite_mode_is_refused_at_begin(shared_pool: EditorPool) -> None:
    sb3 = cat_project().to_sb3()
    async with primitive_editor(shared_pool, sb3) as editor:
        oracle = PrimitiveOracle(sb3, [CompositeAction(api="add_block", args={"blockType": "motion_teleport"})])
        with pytest.raises(OracleDivergenceError, match="fails in composite mode at step 1: INVALID_ARG"):
            await oracle.begin(editor)


async def test_act_before_begin_is_an_error() -> None:
    with pytest.raises(RuntimeError, match="begin"):
        await PrimitiveOracle(b"", []).act(None)


async def test_colour_inputs_are_set_through_the_colour_picker(shared_pool: EditorPool) -> None:
    """set_block_field on a colour input opens Scratch's colour picker, not a text editor: the oracle
    sets its three sliders so that Blockly's conversion gives the colour exactly, or, for a colour no
    slider setting gives (#fff700), picks it from the stage with the eyedropper; then it closes it."""
    project = Project()
    cat = project.sprite("Cat", costume=circle_costume("cat", 60, "#fff700"))
    cat.script(
        block("event_whenflagclicked"),
        block(
            "control_if",
            CONDITION=block("sensing_touchingcolor", COLOR="#ff0000"),
            SUBSTACK=[block("looks_say", MESSAGE="hi")],
        ),
    )
    cat.script(
        block("event_whenflagclicked"),
        block("control_wait_until", CONDITION=block("sensing_touchingcolor", COLOR="#00ff00")),
    )
    sb3 = project.to_sb3()
    wanted = ["#1505ff", "#fff700"]
    async with primitive_editor(shared_pool, sb3) as editor:
        await composite.execute(editor, "select_sprite", {"name": "Cat"})
        order = (await editor.call("compositeBlockIds"))["ids"]  # type: ignore[index,call-overload]
        touching = [
            (index, block_id)
            for index, block_id in enumerate(order)
            if block_id and (await editor.call("geometryBlock", {"id": block_id}))["opcode"] == "sensing_touchingcolor"  # type: ignore[index,call-overload]
        ]
        assert len(touching) == 2
        trajectory = [CompositeAction(api="select_sprite", args={"name": "Cat"})] + [
            CompositeAction(api="set_block_field", args={"blockIndex": index, "fieldName": "COLOR", "value": colour})
            for (index, _), colour in zip(touching, wanted, strict=True)
        ]
        oracle = PrimitiveOracle(sb3, trajectory)
        await oracle.begin(editor)
        run = await drive(editor, oracle)
        held = [
            (await editor.call("geometryBlockFields", {"id": block_id}))["inputs"]["COLOR"]  # type: ignore[index,call-overload]
            for _, block_id in touching
        ]
        picker = await editor.call("geometryColourPicker")
    assert held == wanted
    assert isinstance(picker, dict) and picker["open"] is False
    keys = [action for action in run.actions if action.api == "key"]
    clicks = [action for action in run.actions if action.api == "click"]
    # Each field, each slider at least once, the eyedropper and the stage, the workspace to close each picker.
    assert len(clicks) >= 2 + 3 + 2 + 2
    assert len(keys) <= 3 * 12


CROWD_COLUMNS = (260, 420, 580, 740, 900, 1060, 1220)
CROWD_ROWS = 16


def crowded_project() -> Project:
    """Cat: a loose join block left of columns of say blocks that fill the view, one think block among
    them: every straight way from anywhere free to the think block's input crosses say blocks' inputs."""
    project = Project()
    cat = project.sprite("Cat", costume=circle_costume("cat", 10, "#f80"))
    cat.script(block("operator_join", STRING1="a", STRING2="b"), x=20, y=200)
    for column, x in enumerate(CROWD_COLUMNS):
        says = [block("looks_say", MESSAGE="hi") for _ in range(CROWD_ROWS)]
        if column == 1:
            says[CROWD_ROWS // 2 - 4] = block("looks_think", MESSAGE="hm")
        cat.script(block("event_whenflagclicked"), *says, x=x, y=0)
    return project


async def test_a_value_whose_every_path_meets_other_inputs_first_goes_where_its_path_lands(
    shared_pool: EditorPool,
) -> None:
    """No path to the think block's input is clean (each meets a say block's input first) and no free
    spot offers one: the oracle drags along a path whose candidate at the release is the wanted input."""
    sb3 = crowded_project().to_sb3()
    async with primitive_editor(shared_pool, sb3) as editor:
        ids = await cat_ids(editor)
        order = (await editor.call("compositeBlockIds"))["ids"]  # type: ignore[index,call-overload]
        join, think = ids["operator_join"], ids["looks_think"]
        plan = await editor.call(
            "geometryPlanDrag", {"moving": join, "local": "output", "target": think, "remote": "input:MESSAGE"}
        )
        assert isinstance(plan, dict)
        assert not plan["clean"] and plan["lands"], plan
        assert plan.get("staging") is None or not plan["staging"]["clean"], plan
        placement = {"kind": "value_into", "inputName": "MESSAGE"}
        trajectory = [
            CompositeAction(api="select_sprite", args={"name": "Cat"}),
            CompositeAction(
                api="connect_blocks",
                args={
                    "sourceBlockIndex": order.index(join),
                    "targetBlockIndex": order.index(think),
                    "placement": placement,
                },
            ),
        ]
        oracle = PrimitiveOracle(sb3, trajectory)
        await oracle.begin(editor)
        await drive(editor, oracle)  # the oracle checks every step against the composite dry run
        attached = (await editor.call("geometryBlock", {"id": join}))["attachment"]  # type: ignore[index,call-overload]
    assert attached == {"parent": think, "input": "MESSAGE"}


def with_comment(sb3: bytes, sprite: str, x: float, y: float) -> bytes:
    """``sb3`` with a workspace comment (not on a block) at (x, y) of ``sprite``'s workspace."""
    with zipfile.ZipFile(io.BytesIO(sb3)) as source:
        files = {name: source.read(name) for name in source.namelist()}
    project = json.loads(files["project.json"])
    target = next(t for t in project["targets"] if t["name"] == sprite)
    text = "A note that takes a wheel turn for its own text."
    target["comments"] = {
        "note": {"blockId": None, "x": x, "y": y, "width": 200, "height": 200, "minimized": False, "text": text}
    }
    files["project.json"] = json.dumps(project).encode()
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w") as archive:
        for name, data in files.items():
            archive.writestr(name, data)
    return out.getvalue()


async def test_a_wheel_turn_misses_a_comment_over_the_middle_of_the_workspace(shared_pool: EditorPool) -> None:
    async with primitive_editor(shared_pool, with_comment(cat_project().to_sb3(), "Cat", 250, 0)) as editor:
        page, gestures = Page(editor), Gestures(editor.page)
        layout = await page.layout()
        middle = layout.safe_area.centre()
        assert not any(overlay.contains(middle) for overlay in layout.overlays)
        assert await wheel_point(page, layout) == middle
        # An agent drags the comment by its top bar over the middle: it is now drawn over the workspace.
        note = next(o for o in layout.overlays if layout.safe_area.contains(o.centre()))
        drag = {"start_x": note.x + 30, "start_y": note.y + 10, "end_x": middle.x - 20, "end_y": middle.y - 30}
        assert (await gestures.execute("drag_and_drop", {**drag, "duration": 0.3})).success
        await page.wait("quiet", what="the comment to settle")
        covered = await page.layout()
        assert any(overlay.contains(middle) for overlay in covered.overlays), covered.overlays
        point = await wheel_point(page, covered)
        assert not any(overlay.contains(point) for overlay in covered.overlays)
        assert covered.safe_area.contains(point)
        before = (await page.block((await cat_ids(editor))["control_forever"])).rect
        turn = {"direction": "down", "amount": 120, "x": point.x, "y": point.y}
        assert (await gestures.execute("scroll", turn)).success
        await page.wait("quiet", what="the workspace to stop scrolling")
        after = (await page.block((await cat_ids(editor))["control_forever"])).rect
        assert after.y < before.y - 60  # the workspace turned, not the comment's text
