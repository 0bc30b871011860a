"""Planning a whole suite: each task's trajectory planned on a live editor, replayed on a fresh load of
its initial project and checked against the golden again, then written as ``DIR/<task_id>.json``
with ``DIR/plans.json`` describing every task (length, modified blocks, what could not be expressed).

A plan is derived data: it is never written inside the suite (an upstream clone stays as cloned).
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable
from pathlib import Path
from typing import NamedTuple

from pydantic import BaseModel, ConfigDict

from scratchworld_dist._errors import ConfigError
from scratchworld_dist._files import write_atomic
from scratchworld_dist.kinds.tasks.oracle_plan._planner import plan_project, project_differences
from scratchworld_dist.kinds.tasks.oracle_plan._state import ProjectState, read_state
from scratchworld_dist.suites import Suite, Task, UpstreamSuiteLoader, load_suite, loader_for
from workers import composite
from workers.contract import BridgeError, CompositeAction, ProjectFormatError, ProjectLimits, check_project
from workers.editor import BrowserSession, Editor

PLANS_FILE = "plans.json"


class TaskPlanRecord(BaseModel):
    """What planning one task gave."""

    model_config = ConfigDict(frozen=True)

    task_id: str
    category: str
    actions: int = 0
    modified_blocks: int = 0
    reached_golden: bool = False
    """Planning ended with the golden's scripts and variables in every target."""

    replayed: bool = False
    """The written trajectory, replayed on a fresh load of the initial project, is accepted call by call
    and ends with the scripts and variables planning ended with."""

    lacks: list[str] = []
    trajectory: str | None = None
    """File name of the trajectory in the plan folder (None: nothing was planned)."""

    error: str | None = None
    seconds: float = 0.0


class TaskPlan(NamedTuple):
    """What ``plan_task`` gives: the record, and the states planning read (None where it did not get that far)."""

    record: TaskPlanRecord
    golden: ProjectState | None = None
    """The golden project's scripts and variables, which planning aimed at."""

    planned: ProjectState | None = None
    """Where planning ended (a replay of the trajectory must end there too)."""


class SuitePlans(BaseModel):
    """``plans.json``: every task's record, for reports and the oracle benchmark."""

    suite: str
    root: str
    tasks: list[TaskPlanRecord]


def planning_suite(suite_dir: Path) -> Suite:
    """The suite at ``suite_dir``; an upstream clone needs only its projects here, not its evaluation scripts."""
    loader, root = loader_for(Path(suite_dir).expanduser().absolute())
    if isinstance(loader, UpstreamSuiteLoader):
        return UpstreamSuiteLoader(require_scripts=False).load(root)
    return load_suite(root)


def plan_folder(out: Path, suite: Suite) -> Path:
    """``out``, resolved and created; refused when it lies inside the suite (plans never go into a suite or clone)."""
    resolved = out.expanduser().resolve()
    if resolved.is_relative_to(suite.root.resolve()):
        raise ConfigError(f"--out {out} is inside the suite {suite.root}: plans are written outside it")
    resolved.mkdir(parents=True, exist_ok=True)
    return resolved


async def plan_suite(
    suite: Suite,
    tasks: list[Task],
    out: Path,
    on_task: Callable[[TaskPlanRecord], None] | None = None,
    editor: Editor | None = None,
) -> SuitePlans:
    """Plan, replay and write every task of ``tasks`` into ``out`` (a ``plan_folder``); ``out/plans.json``
    is rewritten after each task. Plans in ``editor`` when given (every task loads its own projects),
    else in a browser of its own."""
    if editor is None:
        async with BrowserSession() as session, session.editor() as own:
            return await plan_suite(suite, tasks, out, on_task, own)
    plans = SuitePlans(suite=suite.name, root=str(suite.root), tasks=[])
    for task in tasks:
        record = (await plan_task(editor, task, out)).record
        plans = plans.model_copy(update={"tasks": [*plans.tasks, record]})
        write_plans(out, plans)
        if on_task is not None:
            on_task(record)
    return plans


def write_plans(out: Path, plans: SuitePlans) -> None:
    """``out/plans.json``, replaced whole (a reader never sees half of it)."""
    write_atomic(out / PLANS_FILE, plans.model_dump_json(indent=2).encode())


async def plan_task(editor: Editor, task: Task, out: Path, *, replay: bool = True) -> TaskPlan:
    """Plan and replay one task in ``editor`` (whatever it holds: the task loads its own projects) and write
    its trajectory as ``out/<task_id>.json``; a task whose files or page fail gets a record with the error.
    ``replay=False`` leaves the replay to the caller (the oracle benchmark replays every plan as an episode
    does, and sets ``replayed`` from that): the record's ``replayed`` stays False."""
    started = time.monotonic()
    base = {"task_id": task.id, "category": task.category}
    if task.golden_project is None:
        return TaskPlan(TaskPlanRecord(**base, error="the task has no golden project"))
    try:
        initial, golden_bytes = _read(task.initial_project), _read(task.golden_project)
        await editor.load_project(golden_bytes)
        golden = await read_state(editor)
        await editor.load_project(initial)
        plan = await plan_project(editor, golden)
        planned = await read_state(editor)
        replayed = replay and await _replays(editor, initial, plan.actions, planned)
    except (OSError, ProjectFormatError, BridgeError) as exc:  # this task's files or page; the next may be fine
        error = f"{type(exc).__name__}: {exc}"
        return TaskPlan(TaskPlanRecord(**base, error=error, seconds=time.monotonic() - started))
    name = f"{task.id}.json"
    lines = ",\n".join("  " + json.dumps({"api": a.api, "args": a.args}, sort_keys=True) for a in plan.actions)
    write_atomic(out / name, f"[\n{lines}\n]\n".encode() if lines else b"[]\n")
    record = TaskPlanRecord(
        **base,
        actions=len(plan.actions),
        modified_blocks=plan.modified_blocks,
        reached_golden=plan.reached_golden,
        replayed=replayed,
        lacks=plan.lacks,
        trajectory=name,
        seconds=time.monotonic() - started,
    )
    return TaskPlan(record, golden, planned)


def _read(path: Path) -> bytes:
    data = path.read_bytes()
    check_project(data, ProjectLimits())
    return data


async def _replays(editor: Editor, initial: bytes, actions: list[CompositeAction], planned: ProjectState) -> bool:
    """The trajectory, on a fresh load, is accepted call by call and ends where planning ended."""
    await editor.load_project(initial)
    for action in actions:
        envelope = await composite.execute(editor, action.api, action.args)
        if not envelope.success:
            return False
    return not project_differences(planned, await read_state(editor))
