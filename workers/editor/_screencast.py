"""A page's frames as Chromium composites them (CDP ``Page.startScreencast``), each with its wall-clock time.

Chromium sends a frame only when the page's picture changes, and stops sending once two frames are not
acknowledged, so each one is acknowledged as soon as it arrives; what a consumer does with it (encode it,
show it live) is its own business, on its own time. A screencast reads the compositor's output: it runs
no script in the page and touches none of its clocks, so it cannot move a page's virtual time or change
what an agent or an evaluation sees.
"""

from __future__ import annotations

import asyncio
import base64
import contextlib
import time
from collections.abc import Callable
from dataclasses import dataclass
from types import TracebackType
from typing import Any

from playwright.async_api import CDPSession, Page
from playwright.async_api import Error as PlaywrightError

from workers._held_tasks import HeldTasks, hold
from workers.contract import EditorCrashedError

JPEG_QUALITY = 80
"""Of the frames Chromium sends (the editor's flat colours and text stay sharp; ~40-90 KB a 1280x720 frame)."""


@dataclass(frozen=True)
class ScreencastFrame:
    """One composited picture of the page."""

    jpeg: bytes
    timestamp: float
    """When Chromium composited it, in seconds since the epoch (the worker's wall clock)."""

    width: int
    height: int
    """The page's size in CSS pixels when it was composited (the JPEG's own may be smaller: ``max_size``)."""


FrameSink = Callable[[ScreencastFrame], None]
"""Receives each frame on the event loop; it must return at once (hand the frame to a queue, a thread...)."""


class Screencast:
    """A page's screencast: ``async with Screencast(page, sink):`` (or ``start``/``stop``) hands ``sink`` every
    frame from start to stop. One at a time per page (Chromium keeps one screencast per page target)."""

    def __init__(
        self,
        page: Page,
        sink: FrameSink,
        *,
        quality: int = JPEG_QUALITY,
        max_size: tuple[int, int] | None = None,
        max_fps: float | None = None,
    ) -> None:
        """``max_size``: frames scaled down to fit (width, height); default: the page's own size. ``max_fps``:
        frames acknowledged at most this often, so Chromium encodes and sends no more (default: every one)."""
        self.page = page
        self.sink = sink
        self.quality = quality
        self.max_size = max_size
        self.min_gap_s = 0.0 if max_fps is None else 1 / max_fps
        self._last_ack = 0.0
        self.frames = 0
        """Frames handed to the sink so far."""
        self._session: CDPSession | None = None
        self._acks: HeldTasks = set()

    async def start(self) -> None:
        """Start receiving frames (the first one, the page as it is, arrives shortly after)."""
        if self._session is not None:
            raise RuntimeError("the screencast is running already")
        params: dict[str, Any] = {"format": "jpeg", "quality": self.quality}
        if self.max_size is not None:
            params |= {"maxWidth": self.max_size[0], "maxHeight": self.max_size[1]}
        try:
            session = await self.page.context.new_cdp_session(self.page)
            session.on("Page.screencastFrame", self._on_frame)
            await session.send("Page.startScreencast", params)
        except PlaywrightError as exc:
            raise EditorCrashedError(f"could not start the page's screencast: {exc.message}") from exc
        self._session = session

    async def stop(self) -> None:
        """Stop the screencast; a page that went away meanwhile is no error (its frames up to then count)."""
        session, self._session = self._session, None
        if session is None:
            return
        for ack in self._acks:  # acknowledgements still held back (``max_fps``): no further frame is wanted
            ack.cancel()
        with contextlib.suppress(PlaywrightError):
            await session.send("Page.stopScreencast")
        if self._acks:
            await asyncio.gather(*self._acks, return_exceptions=True)
        with contextlib.suppress(PlaywrightError):
            await session.detach()

    async def capture(self) -> ScreencastFrame:
        """The page as it is now, through the running screencast's session (e.g. a video's last frame, which the
        screencast may not have sent: it sends none while two are unacknowledged)."""
        if self._session is None:
            raise RuntimeError("start the screencast first")
        size = self.page.viewport_size or {"width": 0, "height": 0}
        try:
            shot = await self._session.send("Page.captureScreenshot", {"format": "jpeg", "quality": self.quality})
        except PlaywrightError as exc:
            raise EditorCrashedError(f"could not capture the page: {exc.message}") from exc
        return ScreencastFrame(base64.b64decode(shot["data"]), time.time(), size["width"], size["height"])

    def _on_frame(self, event: dict[str, Any]) -> None:
        session = self._session
        if session is None:
            return
        now = time.monotonic()
        delay = max(0.0, self._last_ack + self.min_gap_s - now)
        self._last_ack = now + delay
        hold(_ack(session, event["sessionId"], delay), self._acks)  # a page closing under it fails it, harmlessly
        metadata = event.get("metadata") or {}
        stamp = metadata.get("timestamp")
        frame = ScreencastFrame(
            jpeg=base64.b64decode(event["data"]),
            timestamp=float(stamp) if isinstance(stamp, int | float) else time.time(),
            width=round(metadata.get("deviceWidth") or 0),
            height=round(metadata.get("deviceHeight") or 0),
        )
        self.frames += 1
        self.sink(frame)

    async def __aenter__(self) -> Screencast:
        await self.start()
        return self

    async def __aexit__(
        self, exc_type: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None
    ) -> None:
        await self.stop()


async def _ack(session: CDPSession, session_id: int, delay_s: float) -> None:
    if delay_s > 0:
        await asyncio.sleep(delay_s)
    await session.send("Page.screencastFrameAck", {"sessionId": session_id})
