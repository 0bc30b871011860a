"""A drag task on an editor page: set up its view, compute its exact regions, drag for real, verify.

Each function is one bridge call (``scratch-gui/drag/*.js``) or one real gesture, with its reply
typed; the runner and the region benchmark compose them.
"""

from __future__ import annotations

import time

from pydantic import BaseModel, ConfigDict

from workers.contract import DragRegions, DragView, EditorError, ProjectLimits, Region
from workers.editor import Editor
from workers.kinds.drag._contract import DragPayload
from workers.primitive import pressed_moves, settle

SETTLE_MS = 3000
VIEW_TRIES = 3
"""Times a view is placed before the page is given up on (a used page may move it once, restoring an old scroll)."""
DRAG_STEPS = 15
"""Interpolated pointer moves of one drag, as upstream performs it."""


class _Rows(BaseModel):
    model_config = ConfigDict(extra="ignore")

    rows: list[tuple[int, int, int]]


class _Verdict(BaseModel):
    model_config = ConfigDict(extra="ignore")

    connected: bool
    observed: str


class Placed(BaseModel):
    """Where the workspace canvas is: its translation on the workspace SVG (px) and its scale."""

    model_config = ConfigDict(extra="ignore")

    tx: float
    ty: float
    scale: float

    def near(self, other: Placed) -> bool:
        close = abs(self.tx - other.tx) < 0.01 and abs(self.ty - other.ty) < 0.01
        return close and abs(self.scale - other.scale) < 1e-6


class _Ids(BaseModel):
    ids: list[str]


def source_arg(payload: DragPayload) -> dict[str, object]:
    """The source as the page resolves it (a palette variable reporter by its variable's name)."""
    source: dict[str, object] = payload.source.model_dump(mode="json")
    if payload.source.kind == "flyout" and payload.connection.variable_name is not None:
        source["variable_name"] = payload.connection.variable_name
    return source


async def show(
    editor: Editor, project: bytes, view: DragView, limits: ProjectLimits | None = None, *, what: str = "the view"
) -> Placed:
    """Load ``project`` and put the editor in ``view`` (target, palette, scroll, zoom, stage size), settled;
    returns where the canvas was placed (``view_held`` tells later whether it is still there).

    Drag tasks and perception views are both a project shown in a semantic view; raises ``EditorError``
    (naming ``what``) when the page does not settle in that view.
    """
    await editor.load_project(project, limits)
    await editor.set_stage_size(view.stage_size)
    await editor.call("dragSelectTarget", {"sprite": view.sprite})
    await settle(editor, SETTLE_MS)  # the editor draws the target's scripts asynchronously
    for _ in range(VIEW_TRIES):
        placed = Placed.model_validate(await editor.call("dragSetView", view.model_dump(mode="json")))
        await editor.call("dragRendered")  # a palette that reflows after its blocks render clamps the scroll
        if not await settle(editor, SETTLE_MS):
            raise EditorError(f"{what}: the view did not settle within {SETTLE_MS} ms")
        if await view_held(editor, placed):
            return placed
    raise EditorError(f"{what}: the editor moved the view away each of {VIEW_TRIES} times it was placed")


async def view_held(editor: Editor, placed: Placed) -> bool:
    """Whether the canvas is still where ``show`` placed it."""
    return Placed.model_validate(await editor.call("dragViewState")).near(placed)


async def set_up(editor: Editor, payload: DragPayload, limits: ProjectLimits | None = None) -> None:
    """Load the task's project and put the editor in the task's view, settled."""
    await show(editor, payload.initial_project, payload.view, limits, what=f"drag task {payload.task_id}")


async def start_region(editor: Editor, payload: DragPayload) -> Region:
    reply = _Rows.model_validate(await editor.call("dragStartRegion", {"source": source_arg(payload)}))
    return Region(rows=tuple(reply.rows))


async def end_region(editor: Editor, payload: DragPayload, start: tuple[int, int]) -> Region:
    args = {
        "source": source_arg(payload),
        "start": {"x": start[0], "y": start[1]},
        "reference": payload.reference_block_id,
        "connection": payload.connection.model_dump(mode="json"),
        "steps": DRAG_STEPS,
    }
    return Region(rows=tuple(_Rows.model_validate(await editor.call("dragEndRegion", args)).rows))


async def regions(editor: Editor, payload: DragPayload) -> DragRegions:
    """Both regions at the current view; the end region for a press at the start region's deepest pixel."""
    started = time.perf_counter()
    start = await start_region(editor, payload)
    if start.empty:
        raise EditorError(f"drag task {payload.task_id}: no pixel of the view grabs the source")
    fixed = start.deepest()
    end = await end_region(editor, payload, fixed)
    return DragRegions(start=start, fixed_start=fixed, end=end, computed_s=time.perf_counter() - started)


async def block_ids(editor: Editor) -> list[str]:
    """The editing target's block ids (a palette source is found after the drop as the new one)."""
    return _Ids.model_validate(await editor.call("dragBlockIds")).ids


async def drag(editor: Editor, start: tuple[float, float], end: tuple[float, float], steps: int = DRAG_STEPS) -> None:
    """One real drag: press at ``start``, ``steps`` interpolated moves to ``end``, release; then settle.

    Each move is drawn before the next (as by hand, where moves are frames apart): Blockly draws a
    connection preview on the frame after a move, and what it pushes aside decides the next move's
    candidate, so moves sent faster than frames would make the outcome depend on the machine's speed.
    The moves past Chromium's HTML5-drag decision skip Playwright's drag interception, as an episode's do.
    """
    mouse = editor.page.mouse
    await mouse.move(*start)
    await mouse.down()
    await pressed_moves(
        editor.page, start, end, steps, lambda: editor.call("dragRendered"), lambda: editor.call("primitiveDragging")
    )
    await mouse.up()
    await settle(editor, SETTLE_MS)


async def verify(editor: Editor, payload: DragPayload, before: list[str]) -> tuple[bool, str]:
    """Whether the expected connection is in the VM's blocks, and what the drag left, in words."""
    args = {
        "source": source_arg(payload),
        "reference": payload.reference_block_id,
        "connection": payload.connection.model_dump(mode="json"),
        "before": before,
    }
    verdict = _Verdict.model_validate(await editor.call("dragVerify", args))
    return verdict.connected, verdict.observed
