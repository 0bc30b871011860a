"""One Chromium per worker process; every editor gets an origin of its own in one long-lived context (or,
with ``editor_isolation: context``, a fresh browser context).

The isolation unit is the editor's origin (``workers.editor._shared_context``): a page of its own, storage
kept per origin and cleared when the editor closes, so nothing a previous project did (VM state, globals,
storage, mouse history) can reach the next one, and V8's code cache serves the bundle to every opening
after the second (from the first, in a browser started from the node's cache template: ``_cache_template``).
A fresh context per editor isolates the same things and compiles the bundle every time; it stays
selectable. The editor is served by a server on 127.0.0.1 (at the editor origins and the shared script
origin), and the page reaches nothing else: Chromium sends every request, loopback included, to the editor
server as its proxy, which serves the editor's own files and refuses the rest (see
``workers.editor._server``); UDP (WebRTC) is off, and host names do not resolve. So the sprite
library's CDN requests fail at once, and no task, project or agent can make a page talk to the
node's other services.
"""

from __future__ import annotations

import asyncio
import contextlib
import enum
import functools
import logging
import os
import shutil
import tempfile
from collections.abc import Awaitable
from contextlib import AbstractAsyncContextManager
from pathlib import Path
from types import TracebackType
from typing import Literal, TypeVar

from playwright.async_api import Browser, BrowserContext, Page, Playwright, async_playwright
from playwright.async_api import Error as PlaywrightError
from pydantic import BaseModel, ConfigDict, Field

from workers._held_tasks import hold
from workers.contract import (
    ChromiumNotFoundError,
    EditorBundleMissingError,
    EditorCrashedError,
    EditorError,
    EvaluationPage,
)
from workers.editor._cache_template import OPENINGS_TO_OFFER, CacheTemplate
from workers.editor._editor import Editor, opened
from workers.editor._origins import EditorOrigins
from workers.editor._server import EditorAssets, EditorServer
from workers.editor._shared_context import SharedContext
from workers.editor._switches import launch_args
from workers.node import default_chromium, idle_priority

EditorIsolation = Literal["origin", "context"]

ISOLATION_ENV = "SCRATCHWORLD_EDITOR_ISOLATION"


def default_isolation() -> EditorIsolation:
    """``origin``, or the node's ``SCRATCHWORLD_EDITOR_ISOLATION`` (a node setting, as the Chromium path is)."""
    value = os.environ.get(ISOLATION_ENV, "origin")
    if value == "origin" or value == "context":
        return value
    raise ValueError(f"{ISOLATION_ENV} must be origin or context, not {value!r}")


log = logging.getLogger(__name__)

_T = TypeVar("_T")

RESPONSIVE_TIMEOUT_S = 30.0
"""How long a healthy browser may take to open an empty context, even on a busy machine."""

LOSS_GRACE_S = 5.0
"""How long work in a browser that disconnected may take to fail on its own before it is cut
(failing on its own, it keeps its error message and what it recorded; it takes well under a second)."""

SHUTDOWN_TIMEOUT_S = 30.0
"""Bound on each step of closing a session (the browser, then Playwright's driver)."""


class BrowserConfig(BaseModel):
    """How a worker's Chromium is launched and how long an editor may take to get ready."""

    model_config = ConfigDict(frozen=True)

    executable_path: Path = Field(default_factory=default_chromium)
    """Chromium binary (Debian's package; Playwright's own browser download fails here)."""

    extra_args: tuple[str, ...] = ()
    """Flags appended to ``CHROMIUM_ARGS``."""

    viewport: tuple[int, int] = (1280, 720)
    """Page size in CSS pixels; the benchmark's coordinates assume 1280x720."""

    ready_timeout_s: float = Field(default=60.0, gt=0)
    """Upper bound for a fresh editor to become ready (from when its opening starts)."""

    concurrent_opens: int = Field(default=2, ge=1)
    """Editors this browser opens at once; the others wait their turn. Opening one is CPU-bound (16 at
    once on 2 cores ran past the ready timeout); a browser alone on a 2-core node opens 16 in 19 s two at
    a time, 22 s one at a time. A sweep's workers, one browser per core, open one at a time each
    (``workers.actor``)."""

    editor_isolation: EditorIsolation = Field(default_factory=default_isolation)
    """What keeps an editor apart from the browser's others: an origin of its own in one long-lived context
    (V8's code cache then serves the bundle from the third opening on), or a fresh context each (the
    bundle compiled at every opening). Either isolates storage and pages, and neither changes a verdict or an
    episode (the same pages, bundle, VM and clocks), so it is not part of a job's identity."""

    idle_priority: bool = False
    """Run all the browser's processes in Linux's idle scheduling class: they get only the CPU time that
    other work leaves over (a worker's virtual-clock evaluations give way to its agents' steps)."""


class _State(enum.Enum):
    UNOPENED = "unopened"
    OPEN = "open"
    CLOSED = "closed"


async def _close_quietly(context: BrowserContext) -> None:
    with contextlib.suppress(PlaywrightError):
        await context.close()


def _close_orphan(opening: asyncio.Future[BrowserContext]) -> None:
    if not opening.cancelled() and opening.exception() is None:
        hold(_close_quietly(opening.result()))


def _release_orphan(
    release: functools.partial[Awaitable[None]], origins: EditorOrigins, origin: str, opening: asyncio.Future[Page]
) -> None:
    if opening.cancelled() or opening.exception() is not None:
        origins.release(origin, cleared=True)
    else:
        hold(release([opening.result()]))


async def _bounded(step: Awaitable[None], doing: str) -> None:
    try:
        await asyncio.wait_for(step, SHUTDOWN_TIMEOUT_S)
    except TimeoutError:
        log.warning("%s took over %g s; left behind", doing, SHUTDOWN_TIMEOUT_S)


class BrowserSession:
    """Owns Playwright, one Chromium and the editor server for as long as it is open."""

    def __init__(self, config: BrowserConfig | None = None, assets: EditorAssets | None = None) -> None:
        self.config = config or BrowserConfig()
        self._assets = assets
        self._state = _State.UNOPENED
        self._server: EditorServer | None = None
        self._playwright: Playwright | None = None
        self._browser: Browser | None = None
        self._shared: SharedContext | None = None
        """With ``editor_isolation: origin``: the one context every editor opens in."""
        self._user_data: Path | None = None
        self._template: CacheTemplate | None = None
        """With ``editor_isolation: origin``: the node's warm cache this browser started from or may leave."""
        self._editors_opened = 0
        self._opening = asyncio.Semaphore(self.config.concurrent_opens)
        self._lost = asyncio.Event()
        """Set once the browser disconnected (it died, or the session closed)."""

    @property
    def editor_url(self) -> str:
        if self._server is None:
            raise RuntimeError("the browser session is not open")
        return self._server.url

    @property
    def refused_requests(self) -> list[str]:
        """The latest distinct requests this session's pages (or Chromium itself) made to anything but the editor;
        all were refused."""
        return self._server.refusals.latest if self._server is not None else []

    @property
    def connected(self) -> bool:
        """Open and its Chromium still alive; a session that is not must be replaced."""
        return self._state is _State.OPEN and self._browser is not None and self._browser.is_connected()

    async def start(self) -> BrowserSession:
        if self._state is not _State.UNOPENED:
            raise RuntimeError(f"a browser session cannot be started when {self._state.value}")
        executable = self.config.executable_path
        if not executable.is_file():
            raise ChromiumNotFoundError(
                f"Chromium not found at {executable}: install Debian's `chromium` package "
                "(the README's install command does) or set SCRATCHWORLD_CHROMIUM"
            )
        self._state = _State.OPEN
        try:
            shared = self.config.editor_isolation == "origin"
            origins = EditorOrigins() if shared else None
            self._server = EditorServer(self._assets or EditorAssets(), origins=origins).start()
            self._playwright = await async_playwright().start()
            args = launch_args(self._server.proxy, self.config.extra_args)
            if origins is not None:
                self._shared = await self._launch_shared(executable, args, origins)
                self._browser = self._shared.context.browser
            else:
                self._browser = await self._playwright.chromium.launch(
                    executable_path=str(executable), headless=True, args=args
                )
            if self._browser is None:
                raise EditorError("Playwright gave the persistent context no browser")
            self._browser.on("disconnected", lambda _: self._lost.set())
            await self.keep_idle()
        except PlaywrightError as exc:
            await self.close()
            raise EditorError(f"Chromium at {executable} failed to start: {exc.message}") from exc
        except BaseException:
            await self.close()
            raise
        return self

    async def _launch_shared(self, executable: Path, args: list[str], origins: EditorOrigins) -> SharedContext:
        """A persistent context: V8's code cache lives with the HTTP cache in a profile directory. A shared
        non-persistent (incognito) context keeps none: its openings cost the same from the second on
        (measured, loaded machine: 5.7-6.3 CPU-s each, as a fresh context per editor; persistent: ~3.4 from
        the third). The profile starts as a copy of the node's cache template, when there is one."""
        assert self._playwright is not None
        self._user_data = Path(tempfile.mkdtemp(prefix="scratchworld-browser-"))
        assert self._server is not None
        assets = self._server.assets
        bundle_version = await asyncio.to_thread(lambda: assets.bundle_version)  # hashes 19 MB once per process
        self._template = CacheTemplate.for_node(executable, bundle_version)
        if self._template is not None:
            await asyncio.to_thread(self._template.seed, self._user_data)
        width, height = self.config.viewport
        context = await self._playwright.chromium.launch_persistent_context(
            self._user_data,
            executable_path=str(executable),
            headless=True,
            args=args,
            viewport={"width": width, "height": height},
            device_scale_factor=1,
        )
        shared = SharedContext(context, origins)
        try:
            await shared.start()
        except BaseException:  # the session does not hold the context yet: close it here
            with contextlib.suppress(PlaywrightError):
                await _bounded(context.close(), "closing the shared context")
            raise
        return shared

    async def keep_idle(self) -> int:
        """With ``idle_priority``, move every thread of the browser (back) to the idle class; the number moved.

        Run at launch and after each piece of work: threads a browser creates later start in the class,
        but full suites twice left one of them in the normal class after an evaluation (not reproduced
        alone), and a browser that gives way must not keep a thread that does not."""
        if not self.config.idle_priority or not self.connected:
            return 0
        try:
            pid = await self.browser_pid()
        except PlaywrightError:  # it died meanwhile: nothing to move, and its next use reports the failure
            return 0
        return await asyncio.to_thread(idle_priority, pid)

    async def while_connected(self, work: Awaitable[_T], grace_s: float = LOSS_GRACE_S) -> _T:
        """``work``'s result, unless the browser disconnects first: then ``work`` gets ``grace_s`` to end
        on its own (pages that went away make it fail), after which it is cancelled and
        ``EditorCrashedError`` raised.

        Work waiting on something else (an agent on its model) would otherwise learn of the loss only
        after that wait. And a full suite once saw an episode wait out its whole timeout after its browser
        was closed under it (the call that never came back was not found).
        """
        task = asyncio.ensure_future(work)
        lost = asyncio.ensure_future(self._lost.wait())
        try:
            await asyncio.wait({task, lost}, return_when=asyncio.FIRST_COMPLETED)
            if not task.done():
                await asyncio.wait({task}, timeout=grace_s)
        except asyncio.CancelledError:  # our caller gave up (a timeout): so does the work, cleaning up first
            task.cancel()
            await asyncio.wait({task})
            raise
        finally:
            lost.cancel()
        if task.done():
            return task.result()
        task.cancel()
        await asyncio.wait({task}, timeout=grace_s)  # its clean-up, unless it swallows the cancellation
        raise EditorCrashedError(f"the browser disconnected, and the work in it did not end within {grace_s:g} s")

    async def browser_pid(self) -> int:
        """The process id of Chromium's browser process (the root of all its processes)."""
        if self._browser is None:
            raise RuntimeError("the browser session is not open")
        cdp = await self._browser.new_browser_cdp_session()
        try:
            processes = (await cdp.send("SystemInfo.getProcessInfo"))["processInfo"]
        finally:
            await cdp.detach()
        return next(int(process["id"]) for process in processes if process["type"] == "browser")

    async def responsive(self, timeout_s: float = RESPONSIVE_TIMEOUT_S) -> bool:
        """Whether the browser still does its work: it opens and closes an empty context in time.

        An editor failure may be one page's (a renderer crashed) or the whole browser's; only
        the second is a reason to close the browser under the pages of other episodes.
        """
        if not self.connected or self._browser is None:
            return False
        try:
            context = await asyncio.wait_for(self._browser.new_context(), timeout_s)
        except (PlaywrightError, TimeoutError):
            return False
        await _close_quietly(context)
        return True

    async def new_context(self) -> BrowserContext:
        """A fresh, isolated browser context with the pinned viewport and pixel ratio."""
        if self._browser is None or self._state is not _State.OPEN:
            raise RuntimeError("the browser session is not open")
        if not self._browser.is_connected():
            raise EditorCrashedError("the browser has disconnected")
        width, height = self.config.viewport
        opening = asyncio.ensure_future(
            self._browser.new_context(viewport={"width": width, "height": height}, device_scale_factor=1)
        )
        try:
            return await asyncio.shield(opening)
        except PlaywrightError as exc:
            raise EditorCrashedError(f"could not open a browser context: {exc.message}") from exc
        except asyncio.CancelledError:
            # The browser creates the context anyway; close it when it arrives so nothing leaks.
            opening.add_done_callback(_close_orphan)
            raise

    async def open_editor(self, kind: EvaluationPage = "editor", *, draw_palette: bool = True) -> Editor:
        """A ready editor (or bare evaluation page) at an origin of its own (or in a fresh context); the caller
        closes it. Waits its turn among this browser's openings (``BrowserConfig.concurrent_opens``).
        ``draw_palette=False``: see ``Editor.open`` (for an editor whose every use loads a project first)."""
        if self._server is None:
            raise RuntimeError("the browser session is not open")
        if kind == "bare" and self._server.assets.bare_missing:
            raise EditorBundleMissingError(self._server.assets.bare_missing)
        async with self._opening:
            return await self._open_editor(kind, draw_palette)

    async def _open_editor(self, kind: EvaluationPage, draw_palette: bool) -> Editor:
        if self._shared is not None:
            return await self._open_shared_editor(kind, self._shared, draw_palette)
        assert self._server is not None
        url = self._server.page_url(kind)
        context = await self.new_context()
        try:
            page = await context.new_page()
        except PlaywrightError as exc:
            await _close_quietly(context)
            raise EditorCrashedError(f"could not open a page: {exc.message}") from exc
        except BaseException:  # cancelled: the context must not outlive the episode
            await _close_quietly(context)
            raise
        editor = Editor(context, page, kind)
        try:
            await editor.open(url, self.config.ready_timeout_s, draw_palette=draw_palette)
        except BaseException:
            await editor.close()
            raise
        return editor

    async def _open_shared_editor(self, kind: EvaluationPage, shared: SharedContext, draw_palette: bool) -> Editor:
        """A page at a fresh origin in the shared context; whatever fails or is cancelled, the page is closed
        and the origin cleared."""
        assert self._server is not None
        if not self.connected:
            raise EditorCrashedError("the browser has disconnected")
        origin = shared.origins.take()
        release = functools.partial(shared.release, origin)
        opening = asyncio.ensure_future(shared.new_page())
        try:
            page = await asyncio.shield(opening)
        except PlaywrightError as exc:
            shared.origins.release(origin, cleared=True)  # no page was there
            raise EditorCrashedError(f"could not open a page: {exc.message}") from exc
        except asyncio.CancelledError:  # the page comes anyway: release it when it does
            opening.add_done_callback(functools.partial(_release_orphan, release, shared.origins, origin))
            raise
        editor = Editor(shared.context, page, kind, release=release)
        try:
            await editor.open(
                self._server.page_url(kind, origin), self.config.ready_timeout_s, draw_palette=draw_palette
            )
        except BaseException:
            await editor.close()
            raise
        self._editors_opened += kind == "editor"
        return editor

    def editor(self, kind: EvaluationPage = "editor") -> AbstractAsyncContextManager[Editor]:
        """A ready editor (or bare evaluation page) at an origin of its own (or in a fresh context), closed on exit."""
        return opened(self.open_editor(kind))

    async def close(self) -> None:
        """Close the browser, Playwright's driver and the editor server; each step bounded, so a browser
        that dies badly cannot hold its worker (a step past its bound is logged and left behind)."""
        clean = self.connected  # a browser that died may have left its caches half written
        self._state = _State.CLOSED
        self._lost.set()
        browser, playwright, server, shared = self._browser, self._playwright, self._server, self._shared
        self._browser = self._playwright = self._server = self._shared = None
        if shared is not None:
            with contextlib.suppress(PlaywrightError):  # already gone
                await _bounded(shared.context.close(), "closing the shared context")
        if browser is not None:
            with contextlib.suppress(PlaywrightError):  # already gone
                await _bounded(browser.close(), "closing Chromium")
        clean = clean and browser is not None and not browser.is_connected()  # gone, not left behind running
        if playwright is not None:
            await _bounded(playwright.stop(), "stopping Playwright's driver")
        if server is not None:
            await asyncio.to_thread(server.stop)
        if self._user_data is not None:
            if clean and self._template is not None and self._editors_opened >= OPENINGS_TO_OFFER:
                await asyncio.to_thread(self._template.offer, self._user_data)
            await asyncio.to_thread(shutil.rmtree, self._user_data, True)
            self._user_data = None

    async def __aenter__(self) -> BrowserSession:
        return await self.start()

    async def __aexit__(
        self, exc_type: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None
    ) -> None:
        await self.close()
