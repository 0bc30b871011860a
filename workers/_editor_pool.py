"""Editors opened ahead of use, so a run of evaluations does not wait 3-4 s for each editor.

An evaluation needs a clean VM. Resetting a used VM would have to undo everything a project can
leave behind (threads, clones, timers, pen and video layers, the GUI's state), so the pool never
reuses an editor: each one is opened in its own browser context, serves one evaluation and is
closed. What the pool saves is only the waiting: the next editor starts up while the current
evaluation runs. An editor waiting in the pool costs about a fifth of a core (the GUI keeps
rendering), so keep ``spare`` at the number of evaluations that run at once.
"""

from __future__ import annotations

import asyncio
import contextlib
from collections import deque
from contextlib import AbstractAsyncContextManager
from types import TracebackType

from workers._browser import BrowserSession
from workers._editor import Editor, opened
from workers._errors import EditorError


class EditorPool:
    """Keeps ``spare`` fresh editors opening in the background; each editor is used once."""

    def __init__(self, session: BrowserSession, spare: int = 1) -> None:
        if spare < 0:
            raise ValueError("spare must be 0 or more")
        self.session = session
        self.spare = spare
        self.opened = 0
        """Editors this pool has started to open (used, waiting, or still starting)."""

        self._opening: deque[asyncio.Task[Editor]] = deque()
        self._closed = False

    async def open_editor(self) -> Editor:
        """A ready editor nobody has used; the caller closes it."""
        if self._closed:
            raise RuntimeError("the editor pool is closed")
        while self._opening:
            prepared = self._opening.popleft()
            self._refill()
            try:
                editor = await prepared
            except EditorError:
                continue  # the browser may have recovered since; the next one or a direct open decides
            if not editor.page.is_closed():
                return editor
            await editor.close()
        self._refill()
        self.opened += 1
        return await self.session.open_editor()

    def editor(self) -> AbstractAsyncContextManager[Editor]:
        """A ready, unused editor, closed on exit (the same contract as ``BrowserSession.editor``)."""
        return opened(self.open_editor())

    async def wait_ready(self) -> None:
        """Wait until the spare editors have finished opening (or failed to)."""
        self._refill()
        await asyncio.wait(list(self._opening))

    def _refill(self) -> None:
        while not self._closed and len(self._opening) < self.spare:
            self.opened += 1
            self._opening.append(asyncio.ensure_future(self.session.open_editor()))

    async def close(self) -> None:
        """Close the editors still waiting or opening."""
        self._closed = True
        opening, self._opening = list(self._opening), deque()
        for task in opening:
            task.cancel()
        for task in opening:
            with contextlib.suppress(BaseException):
                editor = await task
                await editor.close()

    async def __aenter__(self) -> EditorPool:
        return self

    async def __aexit__(
        self, exc_type: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None
    ) -> None:
        await self.close()
