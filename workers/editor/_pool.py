"""Ready editors for evaluations, so that a run of evaluations does not wait seconds for each editor.

Starting an editor (3-5 s of CPU here) costs more than a whole evaluation in virtual time, so the pool
does three things:
- it reuses editors: after an evaluation, ``Editor.recycle`` undoes what the script left in the
  page and compares the page with the fresh one (``scratch-gui/recycle.js``; loading the next
  project resets the VM as Scratch does between projects). An editor with any difference, a
  killed script or ``max_uses`` evaluations behind it is closed instead. A recycled editor waits
  with its VM stopped, which costs next to nothing;
- it opens ``spare`` fresh editors ahead, in their own browser contexts, for when no used editor
  is ready. A fresh editor waits with its VM stepping, about a third of a core, so keep ``spare``
  small;
- bare evaluation pages (``open_editor("bare")``) are reused the same way, apart from editors; the
  spares opened ahead are of the kind last asked for (a pool that lends both kinds in turn, as an
  episode runner's does, keeps ``spare`` at 0, or its spares would be closed as often as opened);
- ``fill`` opens editors ahead of a run of episodes, all at once, and parks them (VM stopped) like
  recycled ones: opening one costs 3-5 s of CPU here (less from a browser's third editor on, with
  the code cache), and opened while other episodes run, it slows their steps down by seconds.
Every editor it opens leaves its palette undrawn until its first project load, which draws that
project's own (``Editor.open``): each use of a pool's editor loads a project first.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import weakref
from collections import Counter, deque
from collections.abc import AsyncIterator
from types import TracebackType

from workers.contract import BridgeError, EditorError, EvaluationPage
from workers.editor._browser import BrowserSession
from workers.editor._editor import Editor

log = logging.getLogger(__name__)

MAX_USES = 40
"""Evaluations per editor before it is closed anyway (the page's caches only grow)."""

RECYCLE_TIMEOUT_S = 30.0
"""A page that needs longer to recycle is closed instead (recycling drains leftover timers)."""


class EditorPool:
    """Hands out ready editors: recycled ones first, else fresh ones opened ahead."""

    def __init__(self, session: BrowserSession, spare: int = 1, max_uses: int = MAX_USES) -> None:
        if spare < 0:
            raise ValueError("spare must be 0 or more")
        if max_uses < 1:
            raise ValueError("max_uses must be at least 1")
        self.session = session
        self.spare = spare
        self.max_uses = max_uses
        self.opened = 0
        """Editors this pool has started to open (in use, waiting, or still starting)."""
        self.reused = 0
        """Times a waiting editor was handed out: recycled clean, or opened ahead by ``fill``."""
        self.discarded: Counter[str] = Counter()
        """Why used editors were closed instead of reused (first difference, or the reason)."""

        self._ready: dict[EvaluationPage, deque[Editor]] = {"editor": deque(), "bare": deque()}
        self._lent: weakref.WeakKeyDictionary[Editor, int] = weakref.WeakKeyDictionary()
        """Editors handed out, with their evaluation count at the time (callers may close them instead)."""
        self._opening: deque[asyncio.Task[Editor]] = deque()
        self._spare_kind: EvaluationPage = "editor"
        """What the spares are: the kind of page last asked for."""
        self._filling = 0
        """Editors ``fill`` is opening."""
        self._closed = False

    @property
    def held(self) -> int:
        """Editors this pool holds: waiting, lent out or still opening."""
        waiting = sum(len(ready) for ready in self._ready.values())
        return waiting + len(self._lent) + len(self._opening) + self._filling

    async def fill(self, count: int, kind: EvaluationPage = "editor") -> int:
        """Open editors (or bare evaluation pages) until the pool holds ``count``; each waits parked (VM stopped)
        until it is lent.

        The session opens a few at a time (``BrowserConfig.concurrent_opens``). Returns how many pages of
        ``kind`` wait ready; one that fails to open is left out (the job that needs it opens its own).
        """
        missing = count - self.held
        if missing > 0 and not self._closed:
            self._filling += missing
            try:
                await asyncio.gather(*(self._open_parked(kind) for _ in range(missing)))
            finally:
                self._filling -= missing
        return len(self._ready[kind])

    async def _open_parked(self, kind: EvaluationPage) -> None:
        self.opened += 1
        try:
            editor = await self._open_fresh(kind)
        except EditorError as exc:
            log.warning("an editor opened ahead failed: %s", exc)
            return
        try:
            # No forced collection of the opening's garbage (0.27 CPU-s, a sixth of an opening): a lent page is
            # collected after its episode's start anyway, and V8 collects a parked one by itself once it has
            # been idle a while (8 parked editors: 197 MB PSS each, 171 MB 40 s later, the same as forced).
            await editor.park()
        except (EditorError, BridgeError) as exc:
            log.warning("an editor opened ahead could not be parked: %s", exc)
            await editor.close()
            return
        if self._closed:
            await editor.close()
        else:
            self._ready[kind].append(editor)

    async def open_editor(self, kind: EvaluationPage = "editor") -> Editor:
        """A ready editor (or bare evaluation page), clean as if fresh; hand it back with ``release`` (or close it)."""
        if self._closed:
            raise RuntimeError("the editor pool is closed")
        ready = self._ready[kind]
        while ready:
            editor = ready.popleft()
            try:
                await editor.resume()
            except (EditorError, BridgeError):
                self.discarded["it could not be resumed"] += 1
                await editor.close()
                continue
            self.reused += 1
            return self._lend(editor)
        if kind != self._spare_kind:  # the spares opening are of the other kind: they wait for their turn
            self._spare_kind = kind
            await self._drop_spares()
        while self._opening:
            prepared = self._opening.popleft()
            self._refill()
            try:
                editor = await prepared
            except EditorError:
                continue  # the browser may have recovered since; the next one or a direct open decides
            if not editor.page.is_closed():
                return self._lend(editor)
            await editor.close()
        self._refill()
        self.opened += 1
        return self._lend(await self._open_fresh(kind))

    async def _open_fresh(self, kind: EvaluationPage) -> Editor:
        """A new page of the browser's, its palette held until its first project load (every use loads one)."""
        return await self.session.open_editor(kind, draw_palette=False)

    def _lend(self, editor: Editor) -> Editor:
        self._lent[editor] = editor.uses
        return editor

    async def release(self, editor: Editor) -> None:
        """Take an editor back: kept for the next evaluation if it recycles clean, else closed."""
        reason = self._unusable(editor, self._lent.pop(editor, None))
        if reason is None:
            try:
                differences = await asyncio.wait_for(editor.recycle(), RECYCLE_TIMEOUT_S)
            except (EditorError, BridgeError, TimeoutError) as exc:
                differences = [f"recycling failed: {type(exc).__name__}"]
            if not differences and not self._closed:
                self._ready[editor.kind].append(editor)
                return
            reason = differences[0] if differences else "the pool closed"
            log.info("editor not reused: %s", "; ".join(differences) or reason)
        self.discarded[reason] += 1
        await editor.close()
        self._refill()

    def _unusable(self, editor: Editor, uses_when_lent: int | None) -> str | None:
        if self._closed:
            return "the pool closed"
        if not editor.reusable or editor.page.is_closed():
            return "the page was killed or went away"
        if uses_when_lent is None or editor.uses == uses_when_lent:
            return "no evaluation or episode ran (it may have been used otherwise)"
        if editor.uses >= self.max_uses:
            return f"{self.max_uses} uses done"
        return None

    @contextlib.asynccontextmanager
    async def editor(self, kind: EvaluationPage = "editor") -> AsyncIterator[Editor]:
        """A ready editor (or bare page) for one evaluation; released on a normal exit, closed on an exception."""
        editor = await self.open_editor(kind)
        try:
            yield editor
        except BaseException:
            await editor.close()
            raise
        await self.release(editor)

    async def wait_ready(self) -> None:
        """Wait until the spare editors have finished opening (or failed to)."""
        self._refill()
        await asyncio.wait(list(self._opening))

    def _refill(self) -> None:
        while not self._closed and len(self._opening) < self.spare:
            self.opened += 1
            self._opening.append(asyncio.ensure_future(self._open_fresh(self._spare_kind)))

    async def _drop_spares(self) -> None:
        """Close the spares opening (or opened) ahead: they are of a kind no longer asked for."""
        opening, self._opening = list(self._opening), deque()
        for task in opening:
            task.cancel()
        for task in opening:
            with contextlib.suppress(BaseException):
                editor = await task
                await editor.close()

    async def close(self) -> None:
        """Close the editors waiting, recycled or still opening."""
        self._closed = True
        ready = [editor for waiting in self._ready.values() for editor in waiting]
        self._ready = {"editor": deque(), "bare": deque()}
        for editor in ready:
            await editor.close()
        await self._drop_spares()

    async def __aenter__(self) -> EditorPool:
        return self

    async def __aexit__(
        self, exc_type: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None
    ) -> None:
        await self.close()
