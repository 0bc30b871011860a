"""``drag make``: drag tasks from any project, framed and proven in a real editor.

Candidates come from ``drag_candidates`` (every connection of every script, detached to be put
back). Each is then given its view in an editor (its scripts centred in the workspace, a palette
source scrolled into view) and kept only if the oracle passes it there: exact regions that are not
empty, and a real drag at their deepest pixels that makes the connection. So every task of a
generated suite is solvable in this editor, and the reason any candidate was dropped is named.
"""

from __future__ import annotations

import tempfile
from collections.abc import Callable
from pathlib import Path

from pydantic import BaseModel

from scratchworld_dist._errors import SuiteError
from scratchworld_dist._files import read_file
from scratchworld_dist.kinds.drag.items._generate import (
    DragCandidate,
    GenerationProblem,
    drag_candidates,
    select_candidates,
)
from scratchworld_dist.kinds.drag.items._native import write_drag_suite
from scratchworld_dist.kinds.drag.items._task import DragTask
from scratchworld_dist.kinds.drag.items._validate import check_of, oracle_drag
from scratchworld_dist.sb3.editing import PaletteBlock, frame_view
from workers.contract import MIB, DragView, ProjectLimits
from workers.editor import BrowserConfig, BrowserSession, Editor, EditorPool
from workers.kinds.drag import DragRunner


class MadeSuite(BaseModel):
    """What ``make_drag_suite`` wrote and what it left out."""

    root: Path
    tasks: int
    candidates: int
    problems: list[str]


async def _frame(editor: Editor, candidate: DragCandidate) -> DragView:
    """The candidate's view: its scripts centred on the small stage's workspace, its palette block in view."""
    palette = None
    if candidate.source.kind == "flyout" and candidate.category is not None:
        palette = PaletteBlock(candidate.source.opcode, candidate.category, candidate.connection.variable_name)
    view, _ = await frame_view(editor, candidate.project, candidate.sprite, candidate.show_block_ids, palette)
    return view


async def prove_tasks(
    candidates: list[DragCandidate], folder: Path, on_problem: Callable[[str], None]
) -> list[DragTask]:
    """The candidates that the oracle passes in their framed view, as tasks with projects under ``folder``."""
    kept: list[DragTask] = []
    async with BrowserSession(BrowserConfig()) as session, EditorPool(session, spare=0) as pool:
        runner = DragRunner(pool)
        for candidate in candidates:
            async with pool.editor() as editor:
                view = await _frame(editor, candidate)
            path = folder / f"{candidate.id}.sb3"
            path.write_bytes(candidate.project)
            task = candidate.task(path, view)
            check = check_of(task, await oracle_drag(runner, task.payload(candidate.project)))
            if check.valid:
                kept.append(task)
                continue
            on_problem(f"{candidate.project_name}: {candidate.id}: the oracle does not pass it ({check.detail})")
    return kept


async def make_drag_suite(
    projects: list[Path],
    out: Path,
    *,
    name: str,
    per_project: int | None,
    seed: int = 0,
    on_problem: Callable[[str], None] = lambda _: None,
) -> MadeSuite:
    """Generate, frame and prove drag tasks from ``projects``; write the ones that pass as a suite at ``out``.

    Raises ``SuiteError``, writing nothing, when no task comes of them: a command asked for tasks that
    made none has failed (before a browser starts when no project gives a candidate).
    """
    limit = int(ProjectLimits().max_file_mb * MIB)
    chosen: list[DragCandidate] = []
    problems: list[str] = []

    def problem(message: str) -> None:
        problems.append(message)
        on_problem(message)

    stems = [project.stem for project in projects]
    for project in projects:
        # Projects named alike (each task's initial.sb3) are told apart by their folder.
        label = project.stem if stems.count(project.stem) == 1 else f"{project.parent.name}-{project.stem}"
        found, trouble = drag_candidates(read_file(project, limit), project_name=label)
        for item in trouble:
            problem(_describe(item))
        chosen.extend(select_candidates(found, limit_per_project=per_project, seed=seed))
    if not chosen:
        raise SuiteError(f"no drag task made: {_none_from(len(projects), problems)}")
    with tempfile.TemporaryDirectory(prefix="scratchworld-drag-") as scratch:
        tasks = await prove_tasks(chosen, Path(scratch), problem)
        if not tasks:
            raise SuiteError(f"no drag task made: none of {len(chosen)} candidate(s) passes the oracle in this editor")
        write_drag_suite(tasks, out, name)
    return MadeSuite(root=out, tasks=len(tasks), candidates=len(chosen), problems=problems)


def _none_from(projects: int, problems: list[str]) -> str:
    """Why ``projects`` gave no candidate, without repeating the problems already reported one by one."""
    if not problems:
        return f"the {projects} project(s) hold no script with a connection to detach"
    return f"none of the {projects} project(s) gives a candidate ({len(problems)} problem(s) reported)"


def _describe(problem: GenerationProblem) -> str:
    return f"{problem.project}: {problem.message}"
