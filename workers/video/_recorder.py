"""Recording an editor page as a video: its screencast, fed to an encoder thread, from ``start`` to ``stop``.

The frames are taken on the wall clock, whatever clock the page runs on: a page on the virtual episode
clock is still between actions and sends no frame then, so its video shows each action and the page time
that follows it, and a viewer lines the two up by the steps' wall-clock times (``VideoInfo.started_at``).
"""

from __future__ import annotations

import asyncio
import time

from playwright.async_api import Page

from workers.contract import EditorError, EpisodeVideo, RecordSettings
from workers.editor import Screencast, ScreencastFrame
from workers.video._encoder import VideoEncoder


class EpisodeRecorder:
    """One page's video: ``await start()``, then ``await (await stop())`` is the video (None when none came)."""

    def __init__(self, page: Page, settings: RecordSettings) -> None:
        self.page = page
        self.settings = settings
        self._encoder: VideoEncoder | None = None
        self._screencast: Screencast | None = None

    async def start(self) -> None:
        self._encoder = VideoEncoder(self.settings.fps, time.time())
        size = (self.settings.width, round(self.settings.width * 9 / 16))
        self._screencast = Screencast(self.page, self._frame, max_fps=self.settings.fps, max_size=size)
        await self._screencast.start()

    def _frame(self, frame: ScreencastFrame) -> None:
        if self._encoder is not None:
            self._encoder.add(frame.timestamp, frame.jpeg)

    async def stop(self) -> asyncio.Future[EpisodeVideo | None]:
        """Stop recording, with the page as it is now as the last frame (when it can still be captured); returns
        at once with the encoding of what is left, to await when the video is needed (an episode's evaluation
        goes on meanwhile). Idempotent: a second call's future holds None."""
        screencast, encoder = self._screencast, self._encoder
        self._screencast = self._encoder = None
        if encoder is None:
            nothing: asyncio.Future[EpisodeVideo | None] = asyncio.get_running_loop().create_future()
            nothing.set_result(None)
            return nothing
        try:
            if screencast is not None:
                try:
                    last = await screencast.capture()
                    encoder.add(last.timestamp, last.jpeg)
                except EditorError:
                    pass  # the page went away: the video ends with the last frame it sent
                finally:
                    await screencast.stop()
        finally:  # ended even when cancelled (an episode past its time limit): the thread then ends by itself
            encoded = encoder.finish(time.time())
        return encoded

    @property
    def frames(self) -> int:
        """Frames received so far."""
        return self._encoder.received if self._encoder is not None else 0
