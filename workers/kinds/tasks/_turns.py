"""Turns for work that should not all run at once (an episode runner's starts, ``STARTS_AT_ONCE``)."""

from __future__ import annotations

import asyncio


class Turns:
    """A limited number of turns, and how many wait for one."""

    def __init__(self, count: int) -> None:
        self.free = asyncio.Semaphore(count)
        self.waiting = 0


class Turn:
    """One of ``Turns``, given back on exit or earlier by ``release`` (once)."""

    def __init__(self, turns: Turns) -> None:
        self._turns = turns
        self._held = False

    async def __aenter__(self) -> Turn:
        self._turns.waiting += 1
        try:
            await self._turns.free.acquire()
        finally:
            self._turns.waiting -= 1
        self._held = True
        return self

    def release(self) -> None:
        if self._held:
            self._held = False
            self._turns.free.release()

    async def __aexit__(self, *exc: object) -> None:
        self.release()
