"""Framing a view in a real editor: a project's scripts centred on the small stage's workspace, at the editor's
default zoom, and a palette block scrolled into view.

Drag tasks and perception views are both framed this way before anything is measured or shown, so the view
a model gets is the one the editor chose for those blocks (``scratch-gui/drag/``'s ``dragFrame``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from pydantic import BaseModel, ConfigDict

from workers.contract import DragView, PaletteCategory
from workers.editor import Editor
from workers.kinds.drag import SETTLE_MS
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
