"""Can every task be solved through the composite API, and through primitive gestures? The harness's upper bound.

For each task of a suite (an upstream clone, or ours): a trajectory is planned from its initial and golden
projects (``scratchworld oracle-plan``), replayed through the composite API, and acted out as real mouse and
keyboard gestures by the primitive oracle (as primitive episodes get the page: small stage), both on a sweep's
episode clock (``--clock``, virtual by default as a sweep's episodes are: page time stands still between actions
and moves around each, a drag's duration between its moves; ``real``: time runs on). Each result is
compared with the golden by structure (scripts, fields, literals, variables; not ids or positions) and, when
the suite has the task's evaluation script, evaluated under both profiles where the golden itself passes.

Prints per task: calls, modified blocks, composite and primitive outcome, and what the API lacks; then
totals, and the mean modified blocks against the paper's (9.14 over its tasks; 16.96 for Compute).

Tasks run ``--lanes`` at a time (default: one per core, and one more to use the real-time waits of the
primitive oracle's gestures), each lane in an editor of its own in one browser, which plans a task (as
``scratchworld oracle-plan`` does, in the lane's editor) and then checks it, so that planning shares the cores
with the other lanes' checks instead of running alone first. The largest tasks go first (by the blocks in which
their initial and golden projects differ: a plan's length is known only once it is planned); the
evaluations borrow recycled pages from one pool, as a sweep's worker does (a page is verified as good as fresh
before it is reused), instead of opening a page for each of a task's six. A lane's editor is recycled before
each task's composite replay and again before its primitive run, as an episode's page is, so no task starts
from what the one before it left in the GUI (the workspace's zoom and scroll, which the GUI hands to the next
project's sprites): which tasks a lane took before, an accident of timing, cannot change an outcome. The
composite replay is also the plan's own (``scratchworld oracle-plan`` replays each plan once more after
planning it; here that replay is this one, and the golden's state is the one planning read).

Run: ``.venv/bin/python benchmarks/upstream_oracle.py [SUITE_DIR] [--out DIR] [--tasks a,b] [--no-primitive]
[--lanes K] [--clock virtual|real]`` (default ``../shared/scratchworld-upstream``; a clone without
``scratch-bench-api`` gets structure only).
"""

from __future__ import annotations

import argparse
import asyncio
import os
import time
from collections import Counter
from pathlib import Path
from statistics import mean

from pydantic import BaseModel

from scratchworld_dist.kinds.tasks.oracle_plan import (
    ProjectState,
    SuitePlans,
    TaskPlan,
    TaskPlanRecord,
    plan_folder,
    plan_task,
    planning_suite,
    project_differences,
    read_state,
    write_plans,
)
from scratchworld_dist.suites import Task
from scratchworld_dist.suites._task import read_trajectory
from workers import composite
from workers.agents._primitive_oracle import OracleDivergenceError, OracleWaitError, PrimitiveOracle
from workers.contract import (
    BridgeError,
    CompositeAction,
    Done,
    EditorError,
    EpisodeClock,
    EvaluationProfile,
    PrimitiveAction,
    ProjectFormatError,
    check_project,
    evaluation_seed,
)
from workers.editor import BrowserSession, Editor, EditorPool
from workers.evaluation import Evaluator
from workers.kinds.tasks._pace import Pace
from workers.primitive import Gestures

PAPER_MEAN = 9.14
PAPER_COMPUTE_MEAN = 16.96
PROFILES: tuple[EvaluationProfile, ...] = ("upstream", "native")


class Outcome(BaseModel):
    """One mode's result for a task: structure against the golden, and verdicts per profile (None: not run)."""

    structure: bool = False
    completed: bool = True
    """Every action was carried out (a refused call, a failed gesture or a divergence stops a run early)."""
    problem: str = ""
    verdicts: dict[str, bool | None] = {}
    seconds: float = 0.0


class OracleRow(BaseModel):
    plan: TaskPlanRecord
    golden: dict[str, bool | None] = {}
    composite: Outcome = Outcome()
    primitive: Outcome | None = None


class Lane:
    """One editor serving task after task, handed out clean each time (recycled, else a fresh one)."""

    def __init__(self, session: BrowserSession) -> None:
        self.session = session
        self.editor: Editor | None = None
        self.replaced = 0
        """Times its editor did not recycle clean and a fresh one took its place."""

    async def clean(self) -> Editor:
        if self.editor is not None:
            try:
                if not await self.editor.recycle():
                    await self.editor.resume()
                    return self.editor
            except (EditorError, BridgeError):  # the page went wrong: a fresh one serves instead
                pass
            self.replaced += 1
            await self.editor.close()
            self.editor = None
        return await self.current()

    async def current(self) -> Editor:
        """The editor as the last task left it: enough for planning, which loads the projects it reads."""
        if self.editor is None:
            self.editor = await self.session.open_editor()
        return self.editor

    async def close(self) -> None:
        if self.editor is not None:
            await self.editor.close()


async def start_episode(editor: Editor, task_id: str, initial: bytes, clock: EpisodeClock, *, primitive: bool) -> Pace:
    """``initial`` loaded as an episode's runner starts it (seed 0): random draws seeded, the primitive stage small,
    the episode's page time begun."""
    await editor.load_project(initial)
    await editor.seed_random(evaluation_seed(task_id, 0))
    if primitive:
        await editor.set_stage_size("small")
    pace = Pace(editor, clock, stage_seen=primitive)  # the primitive oracle's eyedropper reads the stage
    await pace.start()
    return pace


async def replay(
    editor: Editor, task_id: str, initial: bytes, actions: list[CompositeAction], clock: EpisodeClock
) -> tuple[bytes, str]:
    """The composite API's calls, each with its page time around it as in an episode."""
    pace = await start_episode(editor, task_id, initial, clock, primitive=False)
    for action in actions:
        await pace.before_action()
        envelope = await composite.execute(editor, action.api, action.args)
        await pace.after_action()
        if not envelope.success:
            return await editor.save_project(), f"{action.api} refused: {envelope.error}"
    return await editor.save_project(), ""


async def perform(
    editor: Editor, task_id: str, initial: bytes, actions: list[CompositeAction], clock: EpisodeClock
) -> tuple[bytes, str]:
    """The primitive oracle's gestures, executed as an episode executes them, until it says done."""
    pace = await start_episode(editor, task_id, initial, clock, primitive=True)
    oracle = PrimitiveOracle(initial, actions)
    gestures = Gestures(
        editor.page, pace.pass_time if pace.virtual else None, dragging=lambda: editor.call("primitiveDragging")
    )
    try:
        await oracle.begin(editor)
        while not isinstance(action := await oracle.act(None), Done):
            assert isinstance(action, PrimitiveAction), action
            await pace.before_action()
            envelope = await gestures.execute(action.api, action.args)
            await pace.after_action()
            if not envelope.success:
                return await editor.save_project(), f"gesture {action.api} failed: {envelope.error}"
    except OracleDivergenceError as exc:
        return await editor.save_project(), f"diverged: {exc}"
    except OracleWaitError as exc:  # in an episode, retried; here one task's row, not the end of the run
        return await editor.save_project(), f"timed out: {exc}"
    return await editor.save_project(), ""


async def outcome(
    editor: Editor, evaluator: Evaluator, task: Task, project: bytes, problem: str, golden: ProjectState, started: float
) -> Outcome:
    await editor.load_project(project)
    differences = project_differences(golden, await read_state(editor))
    verdicts: dict[str, bool | None] = {}
    for profile in PROFILES:
        verdicts[profile] = (
            (await evaluator.evaluate(project, task.evaluation_spec(profile))).success
            if task.evaluation_script.is_file()
            else None
        )
    return Outcome(
        structure=not differences and not problem,
        completed=not problem,
        problem=problem or "; ".join(differences[:3]),
        verdicts=verdicts,
        seconds=time.monotonic() - started,
    )


async def check_task(
    row: OracleRow,
    task: Task,
    planning: TaskPlan,
    plans: Path,
    primitive: bool,
    lane: Lane,
    evaluator: Evaluator,
    clock: EpisodeClock,
) -> None:
    """The golden's verdicts, then the composite replay's and the primitive oracle's outcomes, into ``row``. The
    composite replay is also the plan's (``planning`` left it to this one): ``replayed`` says whether it was
    accepted call by call and ended where planning ended."""
    golden, planned = planning.golden, planning.planned
    if row.plan.trajectory is None or task.golden_project is None or golden is None or planned is None:
        return
    actions = read_trajectory(plans / row.plan.trajectory)
    initial, golden_bytes = task.initial_project.read_bytes(), task.golden_project.read_bytes()
    if task.evaluation_script.is_file():
        row.golden = {p: (await evaluator.evaluate(golden_bytes, task.evaluation_spec(p))).success for p in PROFILES}
    started = time.monotonic()
    editor = await lane.clean()
    project, problem = await replay(editor, task.id, initial, actions, clock)
    row.composite = await outcome(editor, evaluator, task, project, problem, golden, started)
    replayed = row.composite.completed and not project_differences(planned, await read_state(editor))
    row.plan = row.plan.model_copy(update={"replayed": replayed})
    if primitive:
        started = time.monotonic()
        editor = await lane.clean()
        project, problem = await perform(editor, task.id, initial, actions, clock)
        row.primitive = await outcome(editor, evaluator, task, project, problem, golden, started)
    print(line(row), flush=True)


def estimated_size(task: Task) -> int:
    """The blocks in which the initial and golden projects differ, counted by opcode per sprite, from the files:
    over upstream's 83 tasks it ranks them as their planned calls do (Spearman's rho 0.96)."""
    try:
        initial, golden = _opcodes(task.initial_project), _opcodes(task.golden_project)
    except (OSError, ProjectFormatError):  # planning records what is wrong with the files
        return 0
    empty: Counter[str] = Counter()
    differences = 0
    for name in golden.keys() | initial.keys():
        mine, theirs = initial.get(name, empty), golden.get(name, empty)
        differences += ((mine - theirs) + (theirs - mine)).total()
    return differences


def _opcodes(project: Path | None) -> dict[str, Counter[str]]:
    if project is None:
        return {}
    targets = check_project(project.read_bytes()).get("targets", [])
    return {
        str(target.get("name")): Counter(
            str(block.get("opcode"))
            for block in target["blocks"].values()
            if isinstance(block, dict) and not block.get("shadow")
        )
        for target in targets
        if isinstance(target, dict) and isinstance(target.get("blocks"), dict)
    }


async def check(
    tasks: list[Task], plans: Path, primitive: bool, lanes: int, clock: EpisodeClock
) -> dict[str, OracleRow]:
    """Every task planned, then checked, ``lanes`` at a time: a lane takes the next task when it is done with
    one, the largest first (no large task is left for last)."""
    waiting: asyncio.Queue[Task] = asyncio.Queue()
    for task in sorted(tasks, key=lambda task: -estimated_size(task)):
        waiting.put_nowait(task)
    rows: dict[str, OracleRow] = {}

    async def run_lane(lane: Lane, evaluator: Evaluator) -> None:
        try:
            while not waiting.empty():
                task = waiting.get_nowait()
                planning = await plan_task(await lane.current(), task, plans, replay=False)
                row = rows[task.id] = OracleRow(plan=planning.record)
                await check_task(row, task, planning, plans, primitive, lane, evaluator, clock)
        finally:
            await lane.close()

    async with BrowserSession() as session, EditorPool(session, spare=0) as pool:
        evaluator = Evaluator(session, pool)
        all_lanes = [Lane(session) for _ in range(lanes)]
        await asyncio.gather(*(run_lane(lane, evaluator) for lane in all_lanes))
    print(f"lane editors replaced because they did not recycle clean: {sum(lane.replaced for lane in all_lanes)}")
    return rows


def judged(result: Outcome, golden: dict[str, bool | None]) -> dict[str, bool]:
    """The verdicts that count: those of the profiles the golden itself passes (none without a script)."""
    return {p: ok for p, ok in result.verdicts.items() if ok is not None and golden.get(p)}


def passed(result: Outcome | None, golden: dict[str, bool | None]) -> str:
    if result is None:
        return "-"
    shown = "same" if result.structure else "DIFFERS"
    return " ".join([shown, *(f"{p}:{'pass' if ok else 'FAIL'}" for p, ok in judged(result, golden).items())])


def line(row: OracleRow) -> str:
    plan = row.plan
    text = (
        f"{plan.task_id:<58} {plan.category:<8} {plan.actions:>5} {plan.modified_blocks:>5}  "
        f"{passed(row.composite, row.golden):<28} {passed(row.primitive, row.golden):<28}"
    )
    notes = [*plan.lacks, *(r.problem for r in (row.composite, row.primitive) if r is not None and r.problem)]
    return text + "".join(f"\n      {note}" for note in notes)


def solved(result: Outcome | None, golden: dict[str, bool | None]) -> bool:
    """Solved by the task's own tests where its script exists (every profile the golden passes), by structure
    against the golden where it does not (a held-out script)."""
    if result is None or not result.completed:
        return False
    verdicts = judged(result, golden)
    return all(verdicts.values()) if verdicts else result.structure


def totals(rows: list[OracleRow]) -> None:
    planned = [r for r in rows if r.plan.error is None]
    print(f"\n{len(rows)} tasks, {len(planned)} planned")
    for name, group in [
        (c, [r for r in planned if r.plan.category == c]) for c in ("create", "debug", "extend", "compute")
    ] + [("all", planned)]:
        if not group:
            continue
        composite_ok = sum(r.composite.structure for r in group)
        primitive = [r for r in group if r.primitive is not None]
        primitive_ok = sum(r.primitive.structure for r in primitive if r.primitive is not None)
        composite_solved = sum(solved(r.composite, r.golden) for r in group)
        primitive_solved = sum(solved(r.primitive, r.golden) for r in primitive)
        print(
            f"  {name:<8} {len(group):>3} tasks  mean calls {mean(r.plan.actions for r in group):6.1f}  "
            f"mean modified blocks {mean(r.plan.modified_blocks for r in group):6.2f}  "
            f"composite same as golden {composite_ok}/{len(group)}, solved {composite_solved}/{len(group)}  "
            f"primitive same as golden {primitive_ok}/{len(primitive)}, solved {primitive_solved}/{len(primitive)}"
        )
    print("  solved: the task's own tests pass where its script exists, the structure matches where it does not")
    print(f"  paper: mean modified blocks {PAPER_MEAN} over its tasks, {PAPER_COMPUTE_MEAN} for Compute")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("suite", nargs="?", default="../shared/scratchworld-upstream", type=Path)
    parser.add_argument("--out", type=Path, default=Path("results/upstream-oracle-plans"))
    parser.add_argument("--tasks", default=None, help="comma-separated task ids (default: all)")
    parser.add_argument("--no-primitive", action="store_true", help="skip the primitive oracle's gestures")
    parser.add_argument(
        "--lanes",
        type=int,
        default=(os.cpu_count() or 1) + 1,
        help="tasks checked at once (default: cores + 1: the primitive oracle's gestures wait in real time)",
    )
    parser.add_argument(
        "--clock",
        choices=["virtual", "real"],
        default="virtual",
        help="the episode clock of both runs (default: virtual, as a sweep's episodes)",
    )
    args = parser.parse_args()
    if args.lanes < 1:
        parser.error("--lanes must be at least 1")
    suite = planning_suite(args.suite)
    tasks = suite.select(ids=args.tasks.split(",") if args.tasks else None)
    folder = plan_folder(args.out, suite)
    started = time.monotonic()
    clock = EpisodeClock(mode=args.clock)
    print(f"episode clock: {clock.mode}; plans into {folder}")
    print(f"{'task':<58} {'category':<8} {'calls':>5} {'mod':>5}  {'composite':<28} {'primitive':<28}")
    checked = asyncio.run(check(tasks, folder, primitive=not args.no_primitive, lanes=args.lanes, clock=clock))
    rows = [checked[task.id] for task in tasks]
    write_plans(folder, SuitePlans(suite=suite.name, root=str(suite.root), tasks=[row.plan for row in rows]))
    totals(rows)
    print(f"planning: {sum(row.plan.seconds for row in rows):.0f} s of the lanes' time")
    (folder / "oracle.json").write_text("[\n" + ",\n".join(r.model_dump_json() for r in rows) + "\n]\n")
    print(f"wall time {time.monotonic() - started:.0f} s; rows in {folder / 'oracle.json'}")


if __name__ == "__main__":
    main()
