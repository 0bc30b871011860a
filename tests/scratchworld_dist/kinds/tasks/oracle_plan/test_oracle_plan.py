"""The oracle planner in a real editor: trajectories planned from (initial, golden) reach the golden through
the composite API, replay the same on a fresh page, pass our tasks, and are no longer than the hand-written
golden trajectories by more than half; what the API cannot do is named, not hidden."""

from __future__ import annotations

import json
import shutil
from collections.abc import AsyncIterator
from pathlib import Path

import pytest
from click.testing import CliRunner

from scratchworld_dist._errors import SuiteError
from scratchworld_dist.cli._main import cli
from scratchworld_dist.kinds.tasks import read_task
from scratchworld_dist.kinds.tasks.oracle_plan import (
    ProjectPlan,
    ProjectState,
    plan_project,
    plan_suite,
    planning_suite,
    project_differences,
    read_state,
)
from scratchworld_dist.sb3 import Project, block, circle_costume, variable
from scratchworld_dist.suites import load_suite
from scratchworld_dist.suites._task import read_trajectory
from tests.conftest import SUITE_DIR, pooled_editor
from tests.support.cli_runner import invoke
from workers import composite
from workers.editor import Editor, EditorPool
from workers.evaluation import Evaluator

MAX_LENGTH_RATIO = 1.5


@pytest.fixture(scope="module")
async def editor(shared_pool: EditorPool) -> AsyncIterator[Editor]:
    async with pooled_editor(shared_pool) as page:
        yield page


async def plan_pair(editor: Editor, initial: bytes, golden: bytes) -> tuple[ProjectPlan, list[str]]:
    """The plan from ``initial`` to ``golden``, and how a fresh replay of it differs from the golden."""
    await editor.load_project(golden)
    wanted = await read_state(editor)
    await editor.load_project(initial)
    plan = await plan_project(editor, wanted)
    return plan, project_differences(wanted, await replayed(editor, initial, plan))


async def replayed(editor: Editor, initial: bytes, plan: ProjectPlan) -> ProjectState:
    """The project after the plan's calls on a fresh load of ``initial`` (each call must be accepted)."""
    await editor.load_project(initial)
    for action in plan.actions:
        envelope = await composite.execute(editor, action.api, action.args)
        assert envelope.success, (action, envelope.error)
    return await read_state(editor)


@pytest.mark.browser
@pytest.mark.slow
async def test_planned_trajectories_solve_our_suite_and_are_not_longer_than_the_hand_written(
    tmp_path: Path, evaluator: Evaluator, editor: Editor
) -> None:
    suite = load_suite(SUITE_DIR)
    plans = await plan_suite(suite, list(suite.tasks), tmp_path, editor=editor)
    assert [r.task_id for r in plans.tasks] == [t.id for t in suite.tasks]
    on_disk = json.loads((tmp_path / "plans.json").read_text())
    assert [r["task_id"] for r in on_disk["tasks"]] == [t.id for t in suite.tasks]
    for record, task in zip(plans.tasks, suite.tasks, strict=True):
        assert record.reached_golden and record.replayed and not record.lacks, record
        planned = read_trajectory(tmp_path / f"{task.id}.json")
        hand_written = task.trajectory() or []
        assert len(planned) == record.actions
        assert len(planned) <= MAX_LENGTH_RATIO * len(hand_written), (task.id, len(planned), len(hand_written))
        await editor.load_project(task.initial_project.read_bytes())
        for action in planned:
            assert (await composite.execute(editor, action.api, action.args)).success
        result = await evaluator.evaluate(await editor.save_project(), task.evaluation_spec())
        assert result.success, (task.id, result.model_dump(include={"passed", "total", "error"}))


def fixed_project() -> bytes:
    """The golden of the hard case: a variable, a reordered loop holding a reporter, a moved and edited block."""
    project = Project()
    cat = project.sprite("Cat", costume=circle_costume("cat", 10, "#f80"))
    cat.variable("score")
    cat.script(
        block("event_whenflagclicked"),
        block("data_setvariableto", VARIABLE="score", VALUE=0),
        block(
            "control_forever",
            SUBSTACK=[block("motion_turnright", DEGREES=15), block("motion_movesteps", STEPS=variable("score"))],
        ),
    )
    cat.script(block("event_whenkeypressed", KEY_OPTION="space"), block("looks_say", MESSAGE="bye"))
    return project.to_sb3()


def broken_project() -> bytes:
    project = Project()
    cat = project.sprite("Cat", costume=circle_costume("cat", 10, "#f80"))
    cat.script(
        block("event_whenflagclicked"),
        block("looks_say", MESSAGE="hi"),
        block("control_forever", SUBSTACK=[block("motion_movesteps", STEPS=10), block("motion_turnright", DEGREES=15)]),
    )
    cat.script(block("control_repeat", TIMES=3, SUBSTACK=[block("motion_changexby", DX=5)]))
    return project.to_sb3()


@pytest.mark.browser
async def test_a_plan_adds_deletes_moves_reorders_and_edits_until_the_golden(editor: Editor) -> None:
    plan, replay_differs = await plan_pair(editor, broken_project(), fixed_project())
    assert plan.reached_golden and not plan.lacks and not replay_differs
    apis = [a.api for a in plan.actions]
    assert apis[0] == "select_sprite"
    assert {"add_variable", "add_block", "connect_blocks", "delete_block", "set_block_field"} <= set(apis)
    # The say block is kept and moved (not deleted and rebuilt): only the new script's hat is added besides
    # the set block and the reporter, and the repeat loop goes with what it holds in one deletion.
    added = sorted(a.args["blockType"] for a in plan.actions if a.api == "add_block")
    assert added == ["data_setvariableto", "data_variable", "event_whenkeypressed"]
    assert apis.count("delete_block") == 1


@pytest.mark.browser
async def test_what_the_api_cannot_do_is_named(editor: Editor) -> None:
    golden = Project()
    golden.sprite("Hero", costume=circle_costume("hero", 10, "#0a0")).script(
        block("event_whenflagclicked"), block("motion_movesteps", STEPS=10)
    )
    golden.sprite("Extra", costume=circle_costume("extra", 10, "#00f"))
    initial = Project()
    initial.sprite("hero", costume=circle_costume("other", 12, "#0a0"))
    plan, _ = await plan_pair(editor, initial.to_sb3(), golden.to_sb3())
    lacks = "\n".join(plan.lacks)
    assert "sprite 'Extra' is added by the golden (the API cannot add sprites)" in lacks
    assert "sprite 'hero' is named 'Hero' in the golden (the API cannot rename sprites)" in lacks
    assert "Hero: its costumes differ (the API cannot change assets)" in lacks
    assert not plan.reached_golden
    # The sprite whose name differs only in case still gets its scripts.
    await editor.load_project(golden.to_sb3())
    wanted = await read_state(editor)
    assert not [p for p in project_differences(wanted, await replayed(editor, initial.to_sb3(), plan)) if "Hero" in p]


def test_plans_are_never_written_inside_the_suite(tmp_path: Path) -> None:
    result = CliRunner().invoke(cli, ["oracle-plan", str(SUITE_DIR), "--out", str(SUITE_DIR / "plans")])
    assert result.exit_code != 0
    assert "is inside the suite" in str(result.exception)  # main() prints it as one line
    assert not (SUITE_DIR / "plans").exists()


@pytest.mark.browser
def test_the_command_plans_in_a_browser_of_its_own(tmp_path: Path) -> None:
    """``scratchworld oracle-plan`` as a user runs it: a line per task, the trajectory and plans.json written."""
    out = tmp_path / "plans"
    done = invoke("oracle-plan", str(SUITE_DIR), "--out", str(out), "--tasks", "bouncing_ball_stuck")
    assert done.returncode == 0, done.stdout + done.stderr
    said = " ".join(done.stderr.split())
    assert "bouncing_ball_stuck: 2 call(s)" in said and "all 1 task(s) planned and replayed to their golden" in said
    assert len(read_trajectory(out / "bouncing_ball_stuck.json")) == 2
    assert [r["task_id"] for r in json.loads((out / "plans.json").read_text())["tasks"]] == ["bouncing_ball_stuck"]


def test_an_upstream_clone_is_planned_without_its_evaluation_scripts(fake_clone: Path) -> None:
    shutil.rmtree(fake_clone / "scratch-bench-api")
    with pytest.raises(SuiteError):
        load_suite(fake_clone)
    suite = planning_suite(fake_clone)
    assert len(suite.tasks) == 3 and all(t.golden_project is not None for t in suite.tasks)


def test_a_sweep_takes_planned_trajectories_for_tasks_that_ship_none(tmp_path: Path) -> None:
    suite_dir = tmp_path / "suite"
    shutil.copytree(SUITE_DIR, suite_dir)
    (suite_dir / "debug/bouncing_ball_stuck/golden_trajectory.json").unlink()
    task = load_suite(suite_dir).task("bouncing_ball_stuck")
    plans = tmp_path / "plans"
    plans.mkdir()
    with pytest.raises(SuiteError, match="no planned trajectory for task bouncing_ball_stuck"):
        read_task(task, trajectories=plans)
    (plans / "bouncing_ball_stuck.json").write_text(
        '[{"api": "select_sprite", "args": {"name": "Ball"}},'
        ' {"api": "connect_blocks", "args": {"sourceBlockIndex": 4, "targetBlockIndex": 6,'
        ' "placement": {"kind": "stack_after"}}}]'
    )
    without, planned = read_task(task), read_task(task, trajectories=plans)
    assert without.payload.golden_trajectory is None
    assert planned.payload.golden_trajectory is not None and len(planned.payload.golden_trajectory) == 2
    assert planned.task_hash != without.task_hash  # another trajectory: other jobs, never a reused result
    shipped = load_suite(suite_dir).task("quiz_score")
    assert read_task(shipped, trajectories=plans).task_hash == read_task(shipped).task_hash  # shipped ones win
