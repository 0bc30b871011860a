"""The editor pages open in a browser, whichever ``editor_isolation`` it runs (a shared context also holds a
blank page of its own, for clearing origins)."""

from __future__ import annotations

from playwright.async_api import Browser, Page

from workers.node import BARE_PAGE, EDITOR_PAGE


def editor_pages(browser: Browser) -> list[Page]:
    """Open editor and bare evaluation pages, in every context of ``browser``."""
    return [page for context in browser.contexts for page in context.pages if page.url.endswith(PAGE_ENDINGS)]


PAGE_ENDINGS = (f"/{EDITOR_PAGE}", f"/{BARE_PAGE}")
