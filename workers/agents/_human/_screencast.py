"""The editor's page as a stream of JPEG frames (CDP ``Page.startScreencast``), for the person's live view.

Chromium sends a frame when the page repaints and waits for its acknowledgement before the next, so a slow
reader slows the stream instead of queueing frames. (A minimal one for the human agent; the episode video
has its own in ``workers.editor``.)
"""

from __future__ import annotations

import asyncio
import base64
import contextlib
from collections.abc import Callable
from typing import Any

from playwright.async_api import CDPSession, Page
from playwright.async_api import Error as PlaywrightError

JPEG_QUALITY = 70


class Screencast:
    """Frames of one page, handed to ``on_frame`` as they come; ``latest`` for a viewer that joins later."""

    def __init__(self, page: Page, on_frame: Callable[[bytes], None]) -> None:
        self.page = page
        self.on_frame = on_frame
        self.latest: bytes | None = None
        self._session: CDPSession | None = None
        self._acks: set[asyncio.Task[Any]] = set()

    async def start(self) -> None:
        size = self.page.viewport_size or {"width": 1280, "height": 720}
        self._session = await self.page.context.new_cdp_session(self.page)
        self._session.on("Page.screencastFrame", self._frame)
        await self._session.send(
            "Page.startScreencast",
            {"format": "jpeg", "quality": JPEG_QUALITY, "maxWidth": size["width"], "maxHeight": size["height"]},
        )

    def _frame(self, params: dict[str, Any]) -> None:
        self.latest = base64.b64decode(params["data"])
        if self._session is not None:
            ack = asyncio.ensure_future(
                self._session.send("Page.screencastFrameAck", {"sessionId": params["sessionId"]})
            )
            self._acks.add(ack)
            ack.add_done_callback(self._acked)
        self.on_frame(self.latest)

    def _acked(self, ack: asyncio.Task[Any]) -> None:
        self._acks.discard(ack)
        if not ack.cancelled():
            ack.exception()  # a page that went away: the episode notices it by itself

    async def stop(self) -> None:
        session, self._session = self._session, None
        if session is None:
            return
        with contextlib.suppress(PlaywrightError):
            await session.send("Page.stopScreencast")
            await session.detach()
