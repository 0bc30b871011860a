"""Editors in one long-lived browser context, each at an origin of its own (``BrowserConfig.editor_isolation
= "origin"``): what opens an editor's page there and what clears its origin when it closes.

One context lets V8's code cache serve the editor bundle to every opening after the second (a fresh
context per editor compiles the 17 MB bundle from scratch each time). What the context no longer keeps
apart, the origin does: storage, service workers and BroadcastChannel are per origin, and cookies too
with port-bound cookies on (``FEATURES_ENABLED``). When an editor closes, its pages are closed first (so
nothing writes after), then its origin's storage cleared, and only then may its port come round again.

Cookies are the one kind Chromium cannot clear per port: ``Storage.clearDataForOrigin`` clears every
127.0.0.2 port's cookies, live siblings' included. So a closed editor's own cookies (a page can set
only ones its scripts can see, and our server sets none) are expired by a script at its origin, in a
blank page opened there for the purpose, and only when it has some.
"""

from __future__ import annotations

import asyncio
import contextlib
import itertools
import json
import logging

from playwright.async_api import BrowserContext, CDPSession, Page
from playwright.async_api import Error as PlaywrightError

from workers.editor._origins import EDITOR_HOST, EditorOrigins

log = logging.getLogger(__name__)

CLEARED_STORAGE = ",".join(
    (
        "file_systems",
        "indexeddb",
        "local_storage",
        "shader_cache",
        "websql",
        "service_workers",
        "cache_storage",
        "interest_groups",
        "shared_storage",
        "storage_buckets",
    )
)
"""``Storage.clearDataForOrigin``'s "all" but cookies (cleared per port, see the module docstring)."""

CLEAR_TIMEOUT_S = 15.0

_EXPIRE = """(cookies) => { for (const [name, path, secure] of cookies) {
    document.cookie = `${name}=; expires=Thu, 01 Jan 1970 00:00:00 GMT; path=${path}${secure ? '; Secure' : ''}`;
} }"""


class SharedContext:
    """One persistent context's editor pages, their origins, and the clearing of an origin when its editor closes."""

    def __init__(self, context: BrowserContext, origins: EditorOrigins) -> None:
        self.context = context
        self.origins = origins
        self._keeper: Page | None = None
        self._cdp: CDPSession | None = None
        self._browser_cdp: CDPSession | None = None
        self._windows = itertools.count()

    async def start(self) -> None:
        """Keep the context's first page, blank, for the storage calls (CDP's Storage domain needs a page)."""
        self._keeper = self.context.pages[0] if self.context.pages else await self.context.new_page()
        self._cdp = await self.context.new_cdp_session(self._keeper)
        if self.context.browser is None:
            raise RuntimeError("a persistent context without its browser")
        self._browser_cdp = await self.context.browser.new_browser_cdp_session()

    async def new_page(self) -> Page:
        """A page in a window of its own. Playwright opens a persistent context's pages as tabs of one window,
        and Chromium draws only the window's front tab: a page behind another got 4 animation frames a
        second instead of ~60 (measured), and the oracle's drags went wrong in it."""
        assert self._browser_cdp is not None
        marker = f"about:blank#window-{next(self._windows)}"
        async with self.context.expect_page(lambda page: page.url == marker) as opened:
            await self._browser_cdp.send("Target.createTarget", {"url": marker, "newWindow": True})
        return await opened.value

    async def release(self, origin: str, pages: list[Page]) -> None:
        """Close ``pages`` (an editor's page and its popups), clear ``origin`` and give its port back; a port
        whose origin could not be cleared is never handed out again."""
        for page in pages:
            with contextlib.suppress(PlaywrightError, TimeoutError):
                await asyncio.wait_for(page.close(), CLEAR_TIMEOUT_S)
        cleared = False
        try:
            cleared = await asyncio.wait_for(self._clear(origin), CLEAR_TIMEOUT_S)
        except (PlaywrightError, TimeoutError) as exc:
            log.warning("could not clear the closed editor origin %s (%s); its port is retired", origin, exc)
        finally:
            self.origins.release(origin, cleared=cleared)

    async def _clear(self, origin: str) -> bool:
        assert self._cdp is not None
        await self._cdp.send("Storage.clearDataForOrigin", {"origin": origin, "storageTypes": CLEARED_STORAGE})
        cookies = await self._cookies(origin)
        if cookies:
            page = await self.new_page()
            try:
                await page.goto(f"{origin}/{EDITOR_HOST}-cleared")  # a 404 document at the origin is enough
                await page.evaluate(_EXPIRE, [[c["name"], c["path"], c["secure"]] for c in cookies])
            finally:
                await page.close()
            cookies = await self._cookies(origin)
            if cookies:
                log.warning("cookies of %s survived its clearing: %s", origin, json.dumps(cookies)[:300])
        return not cookies

    async def _cookies(self, origin: str) -> list[dict[str, object]]:
        assert self._cdp is not None
        port = int(origin.rsplit(":", 1)[1])
        found = (await self._cdp.send("Storage.getCookies"))["cookies"]
        return [c for c in found if c["domain"] == EDITOR_HOST and c.get("sourcePort") == port]
