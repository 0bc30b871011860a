"""A pressed left button's mouse moves sent straight to the page, past Playwright's drag interception.

Playwright's mouse checks every move made with the left button down for an HTML5 drag-and-drop it
should carry on with drag events: it sets up listeners in each frame, turns Chromium's drag
interception on, moves, reads the listeners back and turns interception off, seven protocol calls
in turn where the move is one. Chromium decides whether a press starts an HTML5 drag at the press's
first move past its drag threshold (4 px), and never later in that press; so once a drag's pointer is
well past it and the page reports no HTML5 drag under way, the rest of its moves cannot start one and
go to the page as the very ``Input.dispatchMouseEvent`` Playwright would send. A drag's last move
goes through Playwright's mouse again, so that it knows where the pointer is for the release.

``pressed_moves`` is that loop, shared by an episode's drags (``Gestures``) and the drag benchmark's.
"""

from __future__ import annotations

import contextlib
from collections.abc import Awaitable, Callable

from playwright.async_api import CDPSession, Page
from playwright.async_api import Error as PlaywrightError
from pydantic import JsonValue

DECIDED_PX = 8.0
"""Distance from the press (in x or y) by which Chromium has surely decided about an HTML5 drag:
twice its threshold."""


def decided(press: tuple[float, float], point: tuple[float, float]) -> bool:
    """Whether a pointer pressed at ``press`` and now at ``point`` is past where an HTML5 drag could start."""
    return max(abs(point[0] - press[0]), abs(point[1] - press[1])) >= DECIDED_PX


def html5_dragging(reply: JsonValue) -> bool:
    """The bridge's ``primitiveDragging`` reply read: only a plain ``{"dragging": false}`` says none is under
    way (anything else leaves the drag to Playwright's mouse)."""
    return not (isinstance(reply, dict) and reply.get("dragging") is False)


class PressedMoves:
    """Moves of the left button held down (and no key: every key gesture releases what it pressed), over
    a DevTools session of the page's own; ``close`` detaches it."""

    def __init__(self, session: CDPSession) -> None:
        self._session = session

    @classmethod
    async def open(cls, page: Page) -> PressedMoves:
        return cls(await page.context.new_cdp_session(page))

    async def move(self, x: float, y: float) -> None:
        """The move Playwright's mouse would dispatch (its pressure included), without its interception."""
        await self._session.send(
            "Input.dispatchMouseEvent",
            {"type": "mouseMoved", "button": "left", "buttons": 1, "x": x, "y": y, "modifiers": 0, "force": 0.5},
        )

    async def close(self) -> None:
        """Detach; a page that went away meanwhile has nothing left to detach (the move that failed says so)."""
        with contextlib.suppress(PlaywrightError):
            await self._session.detach()


async def pressed_moves(
    page: Page,
    start: tuple[float, float],
    end: tuple[float, float],
    steps: int,
    after_move: Callable[[], Awaitable[object]],
    dragging: Callable[[], Awaitable[JsonValue]] | None,
) -> None:
    """A pressed drag's ``steps`` interpolated moves from ``start`` to ``end``, awaiting ``after_move`` after
    each (page time passing, or a frame drawn).

    ``dragging()`` (the bridge's ``primitiveDragging``) is read once, at the first move past the decision:
    with no HTML5 drag under way, the moves after it but the last go to the page directly. None: every
    move goes through Playwright's mouse.
    """
    direct: PressedMoves | None = None
    try:
        for step in range(1, steps + 1):
            point = (start[0] + (end[0] - start[0]) * step / steps, start[1] + (end[1] - start[1]) * step / steps)
            if direct is not None and step < steps:
                await direct.move(*point)
            else:
                await page.mouse.move(*point)
            await after_move()
            if dragging is not None and step < steps - 1 and decided(start, point):
                if not html5_dragging(await dragging()):
                    direct = await PressedMoves.open(page)
                dragging = None  # Chromium decides once a press
    finally:
        if direct is not None:
            await direct.close()
