"""Editors sharing one browser context (the default ``editor_isolation: origin``) stay apart: storage,
channels and crashes stay with their origin, a closed editor's origin is cleared before it comes round
again, and a page at an editor origin reaches nothing but its own files and the shared scripts."""

from __future__ import annotations

import asyncio

import psutil
import pytest

from tests.support.browser_pages import crash_renderer
from tests.support.loopback import LoopbackListener
from workers.contract import EditorCrashedError
from workers.editor import BrowserConfig, BrowserSession, Editor
from workers.editor._origins import SHARED_ORIGIN
from workers.editor._switches import (
    FEATURES_DISABLED,
    FEATURES_ENABLED,
    PLAYWRIGHT_FEATURES_DISABLED,
    PLAYWRIGHT_FEATURES_ENABLED,
)
from workers.node import BARE_PAGE, EDITOR_PAGE

pytestmark = pytest.mark.browser

WRITE = """async () => {
  document.cookie = 'kept=1';
  localStorage.setItem('kept', '1');
  await new Promise((resolve, reject) => {
    const request = indexedDB.open('kept', 1);
    request.onupgradeneeded = () => request.result.createObjectStore('s');
    request.onsuccess = () => { request.result.close(); resolve(); };
    request.onerror = () => reject(request.error);
  });
  await (await caches.open('kept')).put('/kept', new Response('1'));
}"""

READ = """async () => ({
  cookie: document.cookie,
  local: localStorage.getItem('kept'),
  indexedDB: (await indexedDB.databases()).map((d) => d.name),
  caches: await caches.keys(),
})"""

NOTHING = {"cookie": "", "local": None, "indexedDB": [], "caches": []}
EVERYTHING = {"cookie": "kept=1", "local": "1", "indexedDB": ["kept"], "caches": ["kept"]}

LISTEN = "() => { window.heard = []; new BroadcastChannel('kept').onmessage = (e) => window.heard.push(e.data); }"
SEND = "() => new BroadcastChannel('kept').postMessage('hello')"


def origin(editor: Editor) -> str:
    return editor.page.url.rsplit("/", 1)[0]


async def test_concurrent_editors_share_no_storage_and_no_channel(session: BrowserSession) -> None:
    async with session.editor("bare") as first, session.editor() as second:
        assert origin(first) != origin(second) and origin(first).startswith("http://127.0.0.2:")
        for editor in (first, second):
            await editor.page.evaluate(LISTEN)
        await first.page.evaluate(WRITE)
        await first.page.evaluate(SEND)  # not heard by the sending channel object; by another one in its page
        await first.page.evaluate(LISTEN)
        await first.page.evaluate(SEND)
        await first.page.wait_for_function("window.heard.length >= 2")
        assert await first.page.evaluate(READ) == EVERYTHING
        assert await second.page.evaluate(READ) == NOTHING  # cookies too: port-bound cookies are on
        assert await second.page.evaluate("window.heard") == []


async def test_a_closed_editors_origin_is_cleared_before_it_comes_round_again(session: BrowserSession) -> None:
    assert session._shared is not None
    async with session.editor("bare") as closed:
        await closed.page.evaluate(WRITE)
        assert await closed.page.evaluate(READ) == EVERYTHING
    port = int(origin(closed).rsplit(":", 1)[1])
    async with session.editor("bare") as after:
        assert origin(after) != origin(closed)  # a fresh origin, not the closed one's
        assert await after.page.evaluate(READ) == NOTHING
    session._shared.origins._next = port  # as after the ports wrapped: the closed origin again
    async with session.editor("bare") as again:
        assert origin(again) == origin(closed)
        assert await again.page.evaluate(READ) == NOTHING


async def test_a_crashed_editor_takes_no_sibling_with_it(session: BrowserSession) -> None:
    async with session.editor("bare") as crashed, session.editor("bare") as sibling:
        await crash_renderer(crashed.page)
        with pytest.raises(EditorCrashedError):
            await crashed.status()
        assert (await sibling.status()).vm
        await sibling.page.evaluate(WRITE)  # and its storage still works
    assert await session.responsive()


async def test_a_popup_is_its_editors_own_fails_its_recycling_and_closes_with_it(session: BrowserSession) -> None:
    async with session.editor("bare") as editor, session.editor("bare") as sibling:
        async with editor.page.expect_popup() as opening:
            await editor.page.evaluate("window.open('about:blank')")
        popup = await opening.value
        assert await editor.recycle() == ["the page opened 1 more (a link or popup)"]
        assert await sibling.recycle() != ["the page opened 1 more (a link or popup)"]  # not the sibling's
    assert popup.is_closed()


REACH = """async ([urls, frames]) => {
  for (const url of urls) await fetch(url).catch(() => null);
  await Promise.all(frames.map((url) => new Promise((resolve) => {
    const frame = document.createElement('iframe');
    frame.onload = frame.onerror = resolve;
    frame.src = url;
    document.body.appendChild(frame);
  })));
}"""


async def test_a_page_at_an_editor_origin_reaches_no_sibling_no_shared_page_and_no_other_port(
    session: BrowserSession,
) -> None:
    shared = session.editor_url.rsplit("/", 1)[0]
    with LoopbackListener() as listener:
        async with session.editor("bare") as page, session.editor("bare") as sibling:
            fetched = [
                # The page the sibling loaded: asked for again, not taken from the HTTP cache (one partition
                # for all 127.0.0.2 ports), where a frame could find it too.
                f"{origin(sibling)}/{BARE_PAGE}",
                f"{shared}/{EDITOR_PAGE}",  # the proxy's own address serves pages nothing
                f"{SHARED_ORIGIN}/{EDITOR_PAGE}",  # the shared origin serves the installed scripts only, as scripts
                f"http://127.0.0.1:{listener.port}/other-port",
                "http://example.com/other-host",
            ]
            # A frame at the sibling's origin would have the sibling's storage.
            framed = [f"{origin(sibling)}/sibling-frame", f"{shared}/{BARE_PAGE}", f"{SHARED_ORIGIN}/{BARE_PAGE}"]
            await page.page.evaluate(REACH, [fetched, framed])
            expected = {f"GET {url}" for url in fetched + framed}
            for _ in range(600):  # each was refused when it was answered; bounded for a loaded machine
                if expected <= set(session.refused_requests):
                    break
                await asyncio.sleep(0.05)
            assert expected <= set(session.refused_requests), session.refused_requests
            assert (await sibling.status()).vm
        assert listener.connections == []


async def test_chromium_keeps_playwrights_feature_switches_and_ours(session: BrowserSession) -> None:
    """Chromium keeps the last ``--enable-features`` (and ``--disable-features``): ours come last and carry
    Playwright's too. A Playwright upgrade that changes its lists fails here: update ``PLAYWRIGHT_FEATURES_*``."""
    argv = psutil.Process(await session.browser_pid()).cmdline()
    for switch, playwrights, ours in (
        ("--enable-features=", PLAYWRIGHT_FEATURES_ENABLED, FEATURES_ENABLED),
        ("--disable-features=", PLAYWRIGHT_FEATURES_DISABLED, FEATURES_DISABLED),
    ):
        lists = [arg.removeprefix(switch).split(",") for arg in argv if arg.startswith(switch)]
        assert len(lists) == 2, lists  # Playwright's, then ours
        assert lists[0] == list(playwrights)
        assert lists[1] == [*playwrights, *ours]


async def test_fresh_context_isolation_stays_selectable() -> None:
    async with (
        BrowserSession(BrowserConfig(editor_isolation="context")) as session,
        session.editor("bare") as first,
        session.editor("bare") as second,
    ):
        assert first.context is not second.context
        assert first.page.url == second.page.url == f"{session.editor_url.rsplit('/', 1)[0]}/{BARE_PAGE}"
        await first.page.evaluate(WRITE)
        assert await second.page.evaluate(READ) == NOTHING


async def test_an_editor_page_runs_in_one_renderer_with_no_address_bar_popups(session: BrowserSession) -> None:
    """``FEATURES_DISABLED``: the SVG-import sandbox iframe stays in its page's process (an out-of-process frame
    would be a target of its own) and no window preloads the address bar's WebUI popups."""
    async with session.editor() as first, session.editor() as second:
        for editor in (first, second):  # the sandbox exists once the editor has warmed it
            await editor.page.wait_for_function("() => document.querySelector('iframe[sandbox]') !== null")
        browser = first.page.context.browser
        assert browser is not None
        cdp = await browser.new_browser_cdp_session()
        targets = (await cdp.send("Target.getTargets"))["targetInfos"]
        await cdp.detach()
    assert not [t["url"] for t in targets if t["type"] in ("iframe", "browser_ui")], targets
