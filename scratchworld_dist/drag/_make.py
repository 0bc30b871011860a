"""``drag make``: drag tasks from any project, framed and proven in a real editor.

Candidates come from ``drag_candidates`` (every connection of every script, detached to be put
back). Each is then given its view in an editor (its scripts centred in the workspace, a palette
source scrolled into view) and kept only if the oracle passes it there: exact regions that are not
empty, and a real drag at their deepest pixels that makes the connection. So every task of a
generated suite is solvable in this editor, and the reason any candidate was dropped is named.
"""

from __future__ import annotations

import tempfile
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from pydantic import BaseModel, ConfigDict

from scratchworld_dist._files import read_file
from scratchworld_dist.drag._generate import DragCandidate, GenerationProblem, drag_candidates, select_candidates
from scratchworld_dist.drag._native import write_drag_suite
from scratchworld_dist.drag._task import DragTask
from scratchworld_dist.drag._validate import check_of, oracle_drag
from workers.contract import MIB, DragView, PaletteCategory, ProjectLimits
from workers.drag._page import SETTLE_MS
from workers.drag._runner import DragRunner
from workers.editor import BrowserConfig, BrowserSession, Editor, EditorPool
from workers.primitive import settle

DEFAULT_SCALE = 0.675
"""The zoom Scratch opens a workspace at (a used page may still show its last view's)."""


class _Frame(BaseModel):
    model_config = ConfigDict(extra="ignore")

    scroll_x: float
    scroll_y: float
    scale: float
    fits: bool
    flyout_scroll: float = 0


class MadeSuite(BaseModel):
    """What ``make_drag_suite`` wrote and what it left out."""

    root: Path
    tasks: int
    candidates: int
    problems: list[str]


@dataclass(frozen=True)
class PaletteBlock:
    """A palette block a view scrolls the palette to (a variable's reporter by its variable's name)."""

    opcode: str
    category: PaletteCategory
    variable_name: str | None = None


async def frame_view(
    editor: Editor, project: bytes, sprite: str | None, blocks: Sequence[str], palette: PaletteBlock | None = None
) -> tuple[DragView, bool]:
    """A view of ``project`` that shows the scripts of ``blocks`` centred on the small stage's workspace (from
    their top-left corner when they do not fit), at the editor's default zoom; and whether they fit.

    ``palette`` also scrolls the palette to show that block near its top.
    """
    await editor.load_project(project)
    await editor.set_stage_size("small")
    await editor.call("dragSelectTarget", {"sprite": sprite})
    await settle(editor, SETTLE_MS)
    args: dict[str, object] = {"blocks": list(blocks), "scale": DEFAULT_SCALE}
    if palette is not None:
        args.update(opcode=palette.opcode, category=palette.category)
        if palette.variable_name:
            args["variable_name"] = palette.variable_name
    frame = _Frame.model_validate(await editor.call("dragFrame", args))
    view = DragView(
        sprite=sprite,
        category=palette.category if palette else None,
        flyout_scroll=frame.flyout_scroll if palette else 0,
        scroll_x=round(frame.scroll_x, 3),
        scroll_y=round(frame.scroll_y, 3),
        scale=frame.scale,
    )
    return view, frame.fits


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
    """Generate, frame and prove drag tasks from ``projects``; write the ones that pass as a suite at ``out``."""
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
    with tempfile.TemporaryDirectory(prefix="scratchworld-drag-") as scratch:
        tasks = await prove_tasks(chosen, Path(scratch), problem)
        write_drag_suite(tasks, out, name)
    return MadeSuite(root=out, tasks=len(tasks), candidates=len(chosen), problems=problems)


def _describe(problem: GenerationProblem) -> str:
    return f"{problem.project}: {problem.message}"
