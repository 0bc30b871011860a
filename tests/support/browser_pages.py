"""The editor pages open in a browser, whichever ``editor_isolation`` it runs (a shared context also holds a
blank page of its own, for clearing origins), and killing one page's renderer."""

from __future__ import annotations

import asyncio
import contextlib
from urllib.parse import urlsplit

from playwright.async_api import Browser, Page
from playwright.async_api import Error as PlaywrightError

from workers.node import BARE_PAGE, EDITOR_PAGE


def editor_pages(browser: Browser) -> list[Page]:
    """Open editor and bare evaluation pages, in every context of ``browser`` (an editor opened ahead has a query)."""
    pages = [page for context in browser.contexts for page in context.pages]
    return [page for page in pages if urlsplit(page.url).path.endswith(PAGE_ENDINGS)]


PAGE_ENDINGS = (f"/{EDITOR_PAGE}", f"/{BARE_PAGE}")


async def crash_renderer(page: Page) -> None:
    """Kill ``page``'s renderer process and return once the page reports the crash."""
    crashed = asyncio.Event()
    page.on("crash", lambda _page: crashed.set())
    cdp = await page.context.new_cdp_session(page)
    crashing = asyncio.ensure_future(cdp.send("Page.crash"))  # never answers: the renderer dies
    await asyncio.wait_for(crashed.wait(), 20)
    crashing.cancel()
    with contextlib.suppress(PlaywrightError, asyncio.CancelledError):
        await crashing
