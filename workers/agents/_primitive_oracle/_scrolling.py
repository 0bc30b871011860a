"""Keeping what the next gesture aims at in view: wheel turns over the workspace, and zooming out
when what must be seen at once does not fit."""

from __future__ import annotations

from collections.abc import AsyncIterator, Awaitable, Callable

from workers.agents._primitive_oracle._divergence import OracleDivergenceError
from workers.agents._primitive_oracle._geometry import Layout, Point, Rect
from workers.agents._primitive_oracle._gestures import click, scroll
from workers.agents._primitive_oracle._page import Page
from workers.contract import PrimitiveAction

MAX_SCROLLS = 4
ROOM_SCROLLS = 2
"""Wheel turns down the workspace when its visible part has no room for a dropped block."""
ROOM_ZOOMS = 5
"""Zoom-outs after those, when the wheel turns left no room either: as many as the editor's zoom-out
button gives (0.675 to its minimum 0.3, 1.2 times smaller each), for a tall stack moved as one."""
ROOM_ATTEMPTS = ROOM_SCROLLS + ROOM_ZOOMS
KEEP_IN_VIEW = 24.0
"""Pixels a grab point keeps from the top of the view when the workspace turns to make room."""


async def scroll_into_view(
    page: Page, locate: Callable[[], Awaitable[list[Point]]], what: str
) -> AsyncIterator[PrimitiveAction]:
    """Wheel the workspace until every point ``locate`` finds is inside the safe area."""
    for _ in range(MAX_SCROLLS):
        points = await locate()
        layout = await page.layout()
        if all(layout.safe_area.contains(p) for p in points):
            return
        async for gesture in scroll_towards(page, points, layout):
            yield gesture
    points = await locate()
    area = (await page.layout()).safe_area
    if not all(area.contains(p) for p in points):
        raise OracleDivergenceError(f"{what}: cannot scroll it into view")


async def scroll_towards(page: Page, points: list[Point], layout: Layout) -> AsyncIterator[PrimitiveAction]:
    """Wheel the workspace (as ``layout`` shows it) so that the box around ``points`` is centred in its safe
    area; when the box does not fit, zoom out instead (the caller reads the points again and comes back)."""
    area = layout.safe_area
    xs, ys = [p.x for p in points], [p.y for p in points]
    if max(xs) - min(xs) > area.width or max(ys) - min(ys) > area.height:
        span = f"({max(xs) - min(xs):.0f}, {max(ys) - min(ys):.0f}) px"
        async for gesture in zoom_out(page, f"points spanning {span} do not fit in the workspace at once"):
            yield gesture
        return
    middle = area.centre()
    dx = (min(xs) + max(xs)) / 2 - middle.x if min(xs) < area.x or max(xs) > area.x + area.width else 0.0
    dy = (min(ys) + max(ys)) / 2 - middle.y if min(ys) < area.y or max(ys) > area.y + area.height else 0.0
    if abs(dx) < 1 and abs(dy) < 1:
        return
    yield scroll(dy, dx, await wheel_point(page, layout))
    await page.wait("quiet", what="the workspace to stop scrolling")


async def wheel_point(page: Page, layout: Layout) -> Point:
    """Where a wheel turn scrolls the workspace ``layout`` shows: the middle of its safe area, or the free spot
    nearest to it when something drawn over the workspace covers the middle (a comment would take the turn for
    its text)."""
    middle = layout.safe_area.centre()
    if not any(overlay.contains(middle) for overlay in layout.overlays):
        return middle
    spot = await page.free_spot(1, 1, middle)
    return spot if spot is not None else middle


async def zoom_out(page: Page, why: str) -> AsyncIterator[PrimitiveAction]:
    """Click the workspace's zoom-out button: blocks are drawn smaller, so more of them and more empty
    space fit in the view (``why``: the divergence when the editor cannot zoom out further)."""
    layout = await page.layout()
    if layout.zoom_out is None or layout.scale <= layout.min_scale + 1e-6:
        raise OracleDivergenceError(f"{why} (the workspace cannot zoom out further)")
    yield click(layout.zoom_out.centre())
    await page.wait("quiet", what="the workspace to zoom out")
    if (await page.layout()).scale >= layout.scale:
        raise OracleDivergenceError(f"{why} (a click on the zoom-out button did not zoom out)")


async def make_room(
    page: Page, attempt: int, why: str, moving: Rect | None = None, grab: Point | None = None
) -> AsyncIterator[PrimitiveAction]:
    """Attempt ``attempt`` (from 0) at showing empty workspace: wheel turns down the workspace by half a
    view (there is empty space under the scripts, as far as the workspace scrolls), then zoom-outs.

    Blocks already on the workspace (``moving``, grabbed at ``grab``) must stay grabbable: the wheel turns
    stop short of taking ``grab`` out of view, and blocks over half the view high or wide, or a turn too
    short to show anything new, get a zoom-out instead."""
    layout = await page.layout()
    area = layout.safe_area
    distance = area.height / 2
    if grab is not None:
        distance = min(distance, grab.y - area.y - KEEP_IN_VIEW)
    big = moving is not None and (moving.height > area.height / 2 or moving.width > area.width / 2)
    can_zoom = layout.scale > layout.min_scale + 1e-6
    if attempt >= ROOM_SCROLLS or (can_zoom and (big or distance < area.height / 8)):
        async for gesture in zoom_out(page, why):
            yield gesture
        return
    yield scroll(max(distance, 0.0), 0.0, await wheel_point(page, layout))
    await page.wait("quiet", what="the workspace to stop scrolling")


async def points_of(point: Awaitable[Point | None]) -> list[Point]:
    """One point as a list to scroll into view (none: nothing to scroll to)."""
    found = await point
    return [found] if found is not None else []
