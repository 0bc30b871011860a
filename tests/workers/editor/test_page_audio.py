"""No AudioContext of a waiting page runs, the GUI's own (made on the page's first gesture) included.

Chromium's own account (the DevTools WebAudio domain) is the judge here, not the page's: a context the
page did not track would go unseen by its own report. A running context costs 0.02-0.03 of a core in
silence, so one left running in every recycled page took the node's cores as a sweep went on.
"""

from __future__ import annotations

import asyncio

import pytest

from tests.support.projects import counter_project
from workers.contract import EpisodeClock
from workers.editor import BrowserSession, Editor, EditorPool

pytestmark = pytest.mark.browser


async def chromium_audio_states(editor: Editor, count: int) -> list[str]:
    """The states Chromium reports for the page's AudioContexts, once it has reported ``count`` of them."""
    devtools = await editor.page.context.new_cdp_session(editor.page)
    states: dict[str, str] = {}
    reported = asyncio.Event()

    def note(event: dict) -> None:
        context = event["context"]
        states[context["contextId"]] = context["contextState"]
        if len(states) >= count:
            reported.set()

    devtools.on("WebAudio.contextCreated", note)
    devtools.on("WebAudio.contextChanged", note)
    try:
        await devtools.send("WebAudio.enable")
        await asyncio.wait_for(reported.wait(), 10)
    finally:
        await devtools.detach()
    return sorted(states.values())


async def test_the_guis_own_audio_context_waits_suspended_with_the_page(session: BrowserSession) -> None:
    """A key press makes the GUI create its context; it runs while the lent page runs on the real clock, is
    suspended once the page is recycled, and one made on the virtual clock is suspended from the start."""
    async with EditorPool(session, spare=0) as pool:
        await pool.fill(1)
        async with pool.editor() as editor:
            editor.uses += 1  # an episode's page: it goes back to the pool
            await editor.load_project(counter_project().to_sb3())
            assert (await editor.status()).other_audio == []  # no gesture yet
            await editor.page.keyboard.press("Shift")
            status = await editor.status()
            assert (status.audio, status.other_audio) == ("running", ["running"]), status
        assert not any(pool.discarded.values()), pool.discarded
        waiting = pool._ready["editor"][0]
        status = await waiting.status()
        assert (status.stepping, status.audio, status.other_audio) == (False, "suspended", ["suspended"]), status
        assert await chromium_audio_states(waiting, 4) == ["suspended"] * 4

    async with EditorPool(session, spare=0) as pool:
        await pool.fill(1)
        async with pool.editor() as editor:
            editor.uses += 1
            await editor.load_project(counter_project().to_sb3())
            await editor.start_episode_clock(EpisodeClock(mode="virtual"))
            await editor.page.keyboard.press("Shift")  # the GUI's context is made while the VM's stands still
            assert await chromium_audio_states(editor, 4) == ["suspended"] * 4
            assert (await editor.status()).other_audio == ["suspended"]
