"""Choosing the editing target: a click on a sprite's tile or on the stage selector."""

from __future__ import annotations

from collections.abc import AsyncIterator

from workers.agents._primitive_oracle._divergence import OracleDivergenceError
from workers.agents._primitive_oracle._geometry import Point
from workers.agents._primitive_oracle._gestures import click
from workers.agents._primitive_oracle._plan import PlannedStep, Run
from workers.contract import PrimitiveAction


async def select_sprite(run: Run, step: PlannedStep) -> AsyncIterator[PrimitiveAction]:
    name = str(step.data.get("editingTarget"))
    layout = await run.page.layout()
    if layout.editing_target == name:
        return
    tiles = [tile for tile in layout.targets.sprites if tile.name == name]
    if len(tiles) != 1:
        found = [tile.name for tile in layout.targets.sprites]
        raise OracleDivergenceError(f"{step.describe()}: no single sprite tile named {name!r} (tiles: {found})")
    yield click(tiles[0].rect.centre())
    await run.page.wait("editingTarget", {"name": name}, what=f"sprite {name!r} to be selected")


async def select_stage(run: Run, step: PlannedStep) -> AsyncIterator[PrimitiveAction]:
    name = str(step.data.get("editingTarget"))
    layout = await run.page.layout()
    if layout.editing_target == name:
        return
    rect = layout.targets.stage
    if rect is None:
        raise OracleDivergenceError(f"{step.describe()}: the stage tile is not on the page")
    yield click(Point(x=rect.x + rect.width / 2, y=rect.y + min(60.0, rect.height / 2)))
    await run.page.wait("editingTarget", {"name": name}, what="the stage to be selected")
