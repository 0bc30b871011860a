"""The person's raw input, played into the editor's page with Playwright's mouse and keyboard, in order.

Events queue and one task plays them, so a press never overtakes the move before it. Pointer moves with no
button held only aim the pointer: a later one replaces any still queued. Moves during a drag all go through,
since Scratch starts a drag and shows where a block will snap only on real intermediate moves.
"""

from __future__ import annotations

import asyncio
import contextlib
from collections import deque

from playwright.async_api import Error as PlaywrightError
from playwright.async_api import Page

from workers.agents._human._events import InputEvent, KeyEvent, MouseEvent, WheelEvent


class InputRelay:
    """Plays events into ``page``; ``put`` never waits, ``close`` stops the player."""

    def __init__(self, page: Page) -> None:
        self.page = page
        self._queue: deque[InputEvent] = deque()
        self._waiting = asyncio.Event()
        self._idle = asyncio.Event()
        self._idle.set()
        self._task: asyncio.Task[None] | None = None
        self.failure: PlaywrightError | None = None
        """Why the page stopped taking input (it went away): the episode ends on its own."""

    def start(self) -> None:
        self._task = asyncio.ensure_future(self._play())

    def put(self, event: InputEvent) -> None:
        if _aims(event) and self._queue and _aims(self._queue[-1]):
            self._queue[-1] = event
        else:
            self._queue.append(event)
        self._idle.clear()
        self._waiting.set()

    async def drained(self) -> None:
        """Wait until every event put so far has been played."""
        await self._idle.wait()

    async def close(self) -> None:
        if self._task is not None:
            self._task.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await self._task

    async def _play(self) -> None:
        try:
            await self._playing()
        finally:
            self._idle.set()  # nothing more will be played: no one waits for it

    async def _playing(self) -> None:
        while True:
            await self._waiting.wait()
            while self._queue:
                event = self._queue[0]
                try:
                    await self._one(event)
                except PlaywrightError as exc:
                    if "Unknown key" not in exc.message:
                        self.failure = exc
                        return
                self._queue.popleft()
            self._waiting.clear()
            self._idle.set()

    async def _one(self, event: InputEvent) -> None:
        mouse = self.page.mouse
        if isinstance(event, MouseEvent):
            await mouse.move(event.x, event.y)
            if event.event == "down":
                await mouse.down(button=event.button, click_count=event.clicks)
            elif event.event == "up":
                await mouse.up(button=event.button, click_count=event.clicks)
        elif isinstance(event, WheelEvent):
            await mouse.move(event.x, event.y)
            await mouse.wheel(event.dx, event.dy)
        elif isinstance(event, KeyEvent):
            await self._key(event)

    async def _key(self, event: KeyEvent) -> None:
        keyboard = self.page.keyboard
        if event.event == "up":
            with contextlib.suppress(PlaywrightError):  # a key whose press was typed as text has no release
                await keyboard.up(event.key)
            return
        try:
            await keyboard.down(event.key)
        except PlaywrightError as exc:
            if "Unknown key" not in exc.message or len(event.key) != 1:
                raise
            await keyboard.insert_text(event.key)  # a character the US layout lacks (é, ß): as text


def _aims(event: InputEvent) -> bool:
    """A pointer move with no button held: only where the pointer ends up matters."""
    return isinstance(event, MouseEvent) and event.event == "move" and event.buttons == 0
