"""Moving blocks already on the workspace: connecting, detaching and deleting them by drags.

The editor alone decides what a drop does (snap, insert, bump); the page plans each connecting
drag by replaying Blockly's choice of connection along the mouse path (``geometryPlanDrag``).
"""

from __future__ import annotations

from collections.abc import AsyncIterator
from typing import Any

from workers.agents._primitive_oracle._divergence import OracleDivergenceError
from workers.agents._primitive_oracle._geometry import BlockGeometry, Point
from workers.agents._primitive_oracle._gestures import DRAG_STEPS, click, drag
from workers.agents._primitive_oracle._page import Page
from workers.agents._primitive_oracle._plan import PlannedStep, Run
from workers.agents._primitive_oracle._scrolling import MAX_SCROLLS, ROOM_ATTEMPTS, make_room, scroll_towards, zoom_out
from workers.contract import PrimitiveAction

CLEAN_UP = "Clean up Blocks"
MAX_STAGINGS = 2
"""Free spots a connecting drag may first move the block to: a second one when the path planned from
the first is no longer clean once the block is there."""
MAX_PATH_ZOOMS = 2
"""Zoom-outs a connecting drag may make when no free spot in view offers a path that lands."""


async def connect_blocks(run: Run, step: PlannedStep) -> AsyncIterator[PrimitiveAction]:
    page = run.page
    source = run.live_id(step, "sourceBlockIndex")
    target = run.live_id(step, "targetBlockIndex")
    placement = step.action.args.get("placement")
    if not isinstance(placement, dict):
        raise OracleDivergenceError(f"{step.describe()}: placement must be an object")
    info = await page.block(source)
    shape = info.shape
    # A GUI drag takes the block and everything under it; the composite API moves a non-hat alone.
    if not shape.hat and not shape.reporter and info.next_block:
        async for gesture in _isolate(page, info, info.next_block, step):
            yield gesture
    destination = await page.block(target)
    info = await page.block(source)
    if info.attachment is not None and info.root == destination.root:
        # Picked up, the block leaves its script redrawn (a C-block's mouth closes, an input narrows), and
        # connections near the destination move after the drag was planned: plan it from free space.
        async for gesture in drag_to_free_space(page, source, step):
            yield gesture
        destination = await page.block(target)
    local, remote = connection_pair(placement, destination.attachment is not None)
    moving = await page.block(source)
    hook = _occupied_hook(destination, remote) if local == "previous" else None
    if hook is not None and any(i.kind == "statement" and i.block is None for i in moving.inputs.values()):
        # Blockly hands what hangs there to a C-block's empty mouth (the C-block wraps it), where the
        # composite API puts it under the C-block: it goes to free space first, then under the C-block.
        owner, name, orphan = hook
        async for gesture in drag_to_free_space(page, orphan, step):
            yield gesture
        async for gesture in drag_connection(page, source, local, owner, name, step):
            yield gesture
        async for gesture in drag_connection(page, orphan, "previous", source, "lastNext", step):
            yield gesture
        return
    async for gesture in drag_connection(page, source, local, target, remote, step):
        yield gesture


def _occupied_hook(destination: BlockGeometry, remote: str) -> tuple[str, str, str] | None:
    """(block, connection, block hanging there) when the statement connection ``remote`` of ``destination``
    holds a block; None when it is free (or is no statement connection)."""
    if remote == "next":
        return (destination.id, "next", destination.next_block) if destination.next_block else None
    if remote == "parent" and destination.attachment is not None:
        parent, name = destination.attachment.parent, destination.attachment.input
        return parent, "next" if name is None else f"input:{name}", destination.id
    if remote.startswith("input:"):
        found = destination.inputs.get(remote.removeprefix("input:"))
        if found is not None and found.kind == "statement" and found.block is not None and not found.shadow:
            return destination.id, remote, found.block
    return None


async def detach_blocks(run: Run, step: PlannedStep) -> AsyncIterator[PrimitiveAction]:
    if step.data.get("detached") is False:
        return  # already the first block of its script
    async for gesture in drag_to_free_space(run.page, run.live_id(step, "blockIndex"), step):
        yield gesture


async def delete_block(run: Run, step: PlannedStep) -> AsyncIterator[PrimitiveAction]:
    page = run.page
    block = run.live_id(step, "blockIndex")
    async for gesture in reach(page, block, step):
        yield gesture
    grab = (await page.block(block)).grab
    if grab is None:
        raise OracleDivergenceError(f"{step.describe()}: block {block} cannot be grabbed")
    palette = (await page.layout()).flyout
    yield drag(grab, palette.centre())  # dropped on the palette, blocks are deleted
    await page.wait("quiet", what="the deletion to settle")


async def _isolate(page: Page, info: BlockGeometry, tail: str, step: PlannedStep) -> AsyncIterator[PrimitiveAction]:
    """Leave the block without its ``tail``, the tail taking its place (the composite API's healing)."""
    block = info.id
    attachment = info.attachment
    if attachment is None:
        async for gesture in drag_to_free_space(page, tail, step):
            yield gesture
    else:
        # The block and its tail go to empty space, then the tail goes back where the block hung.
        async for gesture in drag_to_free_space(page, block, step):
            yield gesture
        hook = "next" if attachment.input is None else f"input:{attachment.input}"
        async for gesture in drag_connection(page, tail, "previous", attachment.parent, hook, step):
            yield gesture
    if (await page.block(block)).next_block is not None:
        raise OracleDivergenceError(f"{step.describe()}: could not take block {block} out of its stack alone")


async def drag_connection(
    page: Page, moving: str, local: str, target: str, remote: str, step: PlannedStep
) -> AsyncIterator[PrimitiveAction]:
    """Drag ``moving`` so that its connection ``local`` snaps to connection ``remote`` of ``target``.

    The page replays Blockly's choice of connection along the straight mouse path. A clean path (no
    other connection is ever the candidate) is taken first, from where the block is or from a free
    spot it moves to first; failing that, a path that lands (the candidate at the release is the
    wanted one, other previews on the way replayed as drawn), from where it is or from a free spot.
    """
    args = {"moving": moving, "local": local, "target": target, "remote": remote, "steps": DRAG_STEPS}
    stagings = zooms = 0
    for _ in range(MAX_SCROLLS + MAX_STAGINGS + MAX_PATH_ZOOMS + 1):
        plan = await page.plan_drag(args)
        grab = plan.grab
        if grab is None:
            async for gesture in reach(page, moving, step):
                yield gesture
            continue
        if not plan.end_visible:
            async for gesture in scroll_towards(page, [plan.reference, plan.end], await page.layout()):
                yield gesture
            continue
        staging = plan.staging if stagings < MAX_STAGINGS else None
        if plan.clean or (plan.lands and (staging is None or not staging.clean)):
            yield drag(grab, plan.end)
            await page.wait("quiet", what="the drop to settle")
            return
        if staging is None:
            why = (
                f"{step.describe()}: no clean path to connect {local} of {moving} to {remote} of {target}: "
                f"{plan.reason}"
            )
            if zooms == MAX_PATH_ZOOMS:
                raise OracleDivergenceError(why)
            # Drawn smaller, the scripts leave free spots on sides of the destination the view had no room
            # on (below a script ending at the view's bottom): spots whose paths come in from there.
            async for gesture in zoom_out(page, why):
                yield gesture
            zooms += 1
            continue
        yield drag(grab, staging.end)
        await page.wait("quiet", what="the block to settle on its staging spot")
        stagings += 1
    raise OracleDivergenceError(
        f"{step.describe()}: cannot show {moving} and its destination on {target} in the workspace at once"
    )


async def drag_to_free_space(page: Page, block: str, step: PlannedStep) -> AsyncIterator[PrimitiveAction]:
    """Drag the block (and what hangs under it) to empty workspace, out of every snap radius."""
    async for gesture in reach(page, block, step):
        yield gesture
    info = await page.block(block)
    grab = info.grab
    if grab is None:
        raise OracleDivergenceError(f"{step.describe()}: block {block} cannot be grabbed")
    rect = info.rect
    # A top-level block leaves its own place free; one inside a script must keep off the whole script.
    ignore = [block] if info.root == block else []
    spot = await page.free_spot(rect.width, rect.height, rect.bottom_left, ignore)
    for attempt in range(ROOM_ATTEMPTS):
        if spot is not None:
            break
        why = f"{step.describe()}: no empty part of the visible workspace can take the blocks"
        async for gesture in make_room(page, attempt, why, rect, grab):
            yield gesture
        info = await page.block(block)
        grab, rect = info.grab, info.rect
        if grab is None:
            break  # scrolled out of reach: give up below
        spot = await page.free_spot(rect.width, rect.height, rect.bottom_left, ignore)
    if spot is None or grab is None:
        raise OracleDivergenceError(f"{step.describe()}: no empty part of the visible workspace can take the blocks")
    yield drag(grab, Point(x=spot.x + grab.x - rect.x, y=spot.y + grab.y - rect.y))
    await page.wait("quiet", what="the drop to settle")


async def reach(page: Page, block: str, step: PlannedStep) -> AsyncIterator[PrimitiveAction]:
    """Make a point of the block's body grabbable: scroll to it, or clean up scripts covering it."""
    cleaned = False
    for _ in range(MAX_SCROLLS + 1):
        info = await page.block(block)
        if info.grab is not None:
            return
        middle = info.rect.centre()
        layout = await page.layout()
        if layout.safe_area.contains(middle):
            if cleaned:
                break
            async for gesture in _clean_up(page, step):
                yield gesture
            cleaned = True
        else:
            async for gesture in scroll_towards(page, [middle], layout):
                yield gesture
    raise OracleDivergenceError(f"{step.describe()}: no part of block {block} can be grabbed")


async def _clean_up(page: Page, step: PlannedStep) -> AsyncIterator[PrimitiveAction]:
    """Right-click the workspace background, choose "Clean up Blocks": scripts stop overlapping."""
    spot = await page.free_spot(8, 8, None)
    if spot is None:
        raise OracleDivergenceError(f"{step.describe()}: no empty workspace background to right-click")
    yield PrimitiveAction(api="click", args={"x": spot.x + 4, "y": spot.y + 4, "button": "right"})
    await page.wait("menuOpen", what="the workspace context menu")
    items = [item for item in (await page.menu()).items if item.text == CLEAN_UP]
    if not items or not items[0].visible:
        raise OracleDivergenceError(f"{step.describe()}: the workspace context menu has no visible {CLEAN_UP!r}")
    yield click(items[0].rect.centre())
    await page.wait("menuClosed", what="the context menu to close")
    await page.wait("quiet", what="the scripts to be cleaned up")


def connection_pair(placement: dict[str, Any], target_attached: bool) -> tuple[str, str]:
    """(connection of the dragged block, connection of the destination) that a placement joins.

    ``target_attached``: the destination hangs under another block (matters for stack_before).
    """
    kind, name = placement.get("kind"), placement.get("inputName")
    if kind == "stack_after":
        return "previous", "next"
    if kind == "statement_into":
        return "previous", f"input:{name}"
    if kind == "value_into":
        return "output", f"input:{name}"
    if kind == "stack_before":
        # Inside a script the block goes where the destination hangs (Blockly inserts it);
        # on top of a script the end of the dragged stack meets the destination's top.
        return ("previous", "parent") if target_attached else ("lastNext", "previous")
    if kind == "wrap" and not target_attached:
        return "input:SUBSTACK", "previous"
    raise OracleDivergenceError(f"placement {placement} is not mapped to gestures")


def target_point(dst: BlockGeometry, placement: dict[str, Any]) -> Point | None:
    """The connection on the destination block that the dragged block must meet."""
    kind = placement.get("kind")
    if kind == "stack_after":
        return dst.next
    if kind in ("statement_into", "value_into"):
        return dst.inputs.get(str(placement.get("inputName")))
    if kind in ("stack_before", "wrap"):
        return dst.previous
    return None
