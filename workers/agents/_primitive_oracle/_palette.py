"""What starts in the palette: new blocks dragged out of it, and its Make a Variable / List buttons.

The palette holds every category in one scrolling column; a wheel turn moves it at once, while a
click on the category menu animates the scroll. A new block is dropped in empty workspace near
the block it will be connected to next, so the connecting drag that follows is short.
"""

from __future__ import annotations

from collections.abc import AsyncIterator, Awaitable, Callable

from workers.agents._primitive_oracle._divergence import OracleDivergenceError
from workers.agents._primitive_oracle._fields import ValueKind, fill_prompt, scope_option, set_value
from workers.agents._primitive_oracle._geometry import FlyoutBlock, FlyoutButton, PaletteMiss, Point
from workers.agents._primitive_oracle._gestures import click, drag, fmt, scroll
from workers.agents._primitive_oracle._moves import target_point
from workers.agents._primitive_oracle._page import Page
from workers.agents._primitive_oracle._plan import PlannedStep, Run
from workers.agents._primitive_oracle._scrolling import (
    MAX_SCROLLS,
    ROOM_ATTEMPTS,
    make_room,
    points_of,
    scroll_into_view,
)
from workers.contract import BridgeError, PrimitiveAction

CATEGORIES = {
    "motion_": "Motion",
    "looks_": "Looks",
    "sound_": "Sound",
    "event_": "Events",
    "control_": "Control",
    "sensing_": "Sensing",
    "operator_": "Operators",
    "data_": "Variables",
}
"""The palette category of each opcode prefix (the English labels of the category menu)."""

FLYOUT_MARGIN = 24
"""Pixels between a palette block and the palette's edge after scrolling it into view."""
MAX_WHEEL = 5000
"""The largest wheel turn ``Gestures`` accepts."""

PaletteLocator = Callable[[], Awaitable[FlyoutBlock | FlyoutButton | PaletteMiss]]
Locator = Callable[[], Awaitable[Point | None]]


async def add_block(run: Run, step: PlannedStep) -> AsyncIterator[PrimitiveAction]:
    page = run.page
    opcode = str(step.action.args["blockType"])
    creation = step.action.args.get("creation") or {}
    variable = None
    if opcode in ("data_variable", "data_listcontents") and isinstance(creation, dict):
        name = creation.get("variableName" if opcode == "data_variable" else "listName")
        variable = str(name) if name is not None else None
    category = next((name for prefix, name in CATEGORIES.items() if opcode.startswith(prefix)), None)
    if category is None:
        raise OracleDivergenceError(f"{step.describe()}: no palette category holds {opcode}")

    async def locate() -> FlyoutBlock | PaletteMiss:
        return await page.flyout_block(opcode, variable)

    what = f"{step.describe()}: {opcode}" + (f" for {variable!r}" if variable else "")
    async for gesture in show_in_palette(page, locate, category, what):
        yield gesture
    anchor_of = await _anchor(run, step)
    if anchor_of is not None:
        async for gesture in scroll_into_view(page, lambda: points_of(anchor_of()), f"{step.describe()} (its partner)"):
            yield gesture
    palette, grab = await _palette_block(page, opcode, variable)
    ratio = palette.workspace_scale / palette.flyout_scale
    rect = palette.rect
    spot = None
    for attempt in range(ROOM_ATTEMPTS + 1):
        near = await anchor_of() if anchor_of is not None else None
        spot = await page.free_spot(rect.width * ratio, rect.height * ratio, near)
        if spot is not None or attempt == ROOM_ATTEMPTS:
            break
        why = f"{step.describe()}: no empty part of the workspace can take the block"
        async for gesture in make_room(page, attempt, why):
            yield gesture
        palette, grab = await _palette_block(page, opcode, variable)
        ratio = palette.workspace_scale / palette.flyout_scale
        rect = palette.rect
    if spot is None:
        raise OracleDivergenceError(f"{step.describe()}: no empty part of the workspace can take the block")
    end = Point(x=spot.x + (grab.x - rect.x) * ratio, y=spot.y + (grab.y - rect.y) * ratio)
    known = [block.id for block in (await page.top_blocks()).vm]
    yield drag(grab, end)
    result = await page.wait_result("newBlock", {"opcode": opcode, "known": known})
    if not result.ok:
        raise OracleDivergenceError(
            f"{step.describe()}: dropping {opcode} from the palette at {fmt(end)} did not leave exactly one new "
            f"top-level {opcode} (new ones: {result.value}); did it snap to a script?"
        )
    live_id = str(result.value)
    run.live[f"new:{step.data['blockId']}"] = live_id
    async for gesture in _match_new_fields(page, step, live_id):
        yield gesture


async def add_variable(run: Run, step: PlannedStep) -> AsyncIterator[PrimitiveAction]:
    """``add_variable`` and ``add_list``: the palette's button, then the GUI's prompt."""
    page = run.page
    created = step.data.get("created") or {}
    if not created.get("created"):
        return  # the composite call reused an existing one: nothing to make
    button = "Make a List" if step.action.api == "add_list" else "Make a Variable"

    async def locate() -> FlyoutButton | PaletteMiss:
        return await page.flyout_button(button)

    async for gesture in show_in_palette(page, locate, "Variables", f"{step.describe()}: the {button!r} button"):
        yield gesture
    found = await locate()
    if isinstance(found, PaletteMiss):
        raise OracleDivergenceError(f"{step.describe()}: the {button!r} button left the palette")
    yield click(found.rect.centre())
    async for gesture in fill_prompt(page, str(created["name"]), scope_option(str(created["scope"]))):
        yield gesture


async def show_in_palette(
    page: Page, locate: PaletteLocator, category: str, what: str
) -> AsyncIterator[PrimitiveAction]:
    """Wheel the palette until what ``locate`` finds is usable (visible, and grabbable if a block).

    The category menu is the fallback, when the item is not drawn or a wheel turn does not move it.
    """
    opened = False
    previous: float | None = None
    for _ in range(MAX_SCROLLS + 2):
        found = await locate()
        if isinstance(found, PaletteMiss) or (previous is not None and found.rect.y == previous):
            if opened:
                raise OracleDivergenceError(f"{what} is not in the {category} palette")
            async for gesture in _open_category(page, category):
                yield gesture
            opened, previous = True, None
            continue
        if found.usable:
            return
        view, rect = found.flyout, found.rect
        delta = max(-MAX_WHEEL, min(MAX_WHEEL, rect.y - view.y - FLYOUT_MARGIN))
        previous = rect.y
        yield scroll(delta, 0.0, view.centre())
        await page.wait("flyoutSettled", what="the palette to stop scrolling")
    raise OracleDivergenceError(f"{what} stays out of view in the palette")


async def _open_category(page: Page, category: str) -> AsyncIterator[PrimitiveAction]:
    items = [item for item in (await page.layout()).categories if item.name == category]
    if not items:
        raise OracleDivergenceError(f"the category menu has no {category!r}")
    yield click(items[0].rect.centre())
    await page.wait("flyoutSettled", what=f"the palette to scroll to {category}")


async def _palette_block(page: Page, opcode: str, variable: str | None) -> tuple[FlyoutBlock, Point]:
    """The palette block and the point to press on it, which must still be there."""
    found = await page.flyout_block(opcode, variable)
    if isinstance(found, PaletteMiss) or found.grab is None:
        raise OracleDivergenceError(f"{opcode} is no longer grabbable in the palette")
    return found, found.grab


async def _match_new_fields(page: Page, step: PlannedStep, live_id: str) -> AsyncIterator[PrimitiveAction]:
    """Give a new block the dropdown choices the dry run gave it (e.g. the variable of a set block)."""
    wanted = step.new_fields
    have = await page.block_fields(live_id)
    if wanted is None:
        return
    kinds: tuple[ValueKind, ...] = ("fields", "inputs")
    for kind in kinds:
        for name, value in wanted.values(kind).items():
            if have.values(kind).get(name) != value:
                async for gesture in set_value(page, live_id, name, value, kind, step):
                    yield gesture


async def _anchor(run: Run, step: PlannedStep) -> Locator | None:
    """Where the next connection involving the new block will happen, if its partner is on the page."""
    new_id = f"new:{step.data['blockId']}"
    for later in run.plan[step.number :]:
        if later.action.api != "connect_blocks":
            continue
        source, target = later.blocks.get("sourceBlockIndex"), later.blocks.get("targetBlockIndex")
        if new_id not in (source, target):
            continue
        partner = target if source == new_id else source
        if partner is None or partner not in run.live:
            return None
        placement = later.action.args.get("placement")
        locate = _locator(run.page, run.live[partner], placement if source == new_id else None)
        return locate if await locate() is not None else None
    return None


def _locator(page: Page, block: str, placement: object) -> Locator:
    """Where ``block`` is now: the connection ``placement`` aims at on it, or its top-left corner."""

    async def locate() -> Point | None:
        try:
            info = await page.block(block)
        except BridgeError:
            return None
        point = target_point(info, placement) if isinstance(placement, dict) else None
        return point if point is not None else info.rect.top_left

    return locate
