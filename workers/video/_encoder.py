"""H.264 encoding of screencast frames, in a thread of its own so the worker's event loop never waits on it.

The event loop only queues each frame's JPEG with its wall-clock time (``add``); the thread keeps the newest
frame of each frame period (``FramePeriods``), decodes those JPEGs and encodes them with libx264 (PyAV's
wheel bundles it) into an MP4 in memory, at the niceness of background work so agents' steps come first.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import os
import queue
import tempfile
import threading
import time
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path

import av
import cv2
import numpy as np

from workers.contract import EpisodeVideo, VideoInfo
from workers.video._periods import FramePeriods, Timed

log = logging.getLogger(__name__)

X264_OPTIONS = {"preset": "veryfast", "crf": "30", "tune": "stillimage", "bf": "0"}
"""An editor is flat colours, text and few moving parts: a high CRF keeps text legible; ``veryfast`` costs a
fraction of ``medium``'s CPU for a few percent more bytes. No B-frames: frames come at irregular times (none
while the page is still), and without reordering each frame's decode time is its presentation time, so the
file's timeline (and its duration, up to the held last frame) is the wall clock's."""

KEYFRAME_S = 2
"""At most this long between keyframes: the viewer seeks to any step in a moment."""

ENCODER_NICENESS = 10
"""The encoding thread's niceness: it takes the CPU the browser and the agents leave over."""

MAX_QUEUED_S = 30
"""Frames (in seconds of video) queued at most before newer ones are dropped: an encoder that cannot keep up
(a starved machine) holds bounded memory; ``VideoInfo.received`` still counts them."""


@dataclass(frozen=True)
class _Frame:
    timestamp: float
    jpeg: bytes


@dataclass(frozen=True)
class _End:
    timestamp: float


class VideoEncoder:
    """Frames in (on the event loop), an ``EpisodeVideo`` out (``finish``); one per video."""

    def __init__(self, fps: int, started_at: float) -> None:
        self.fps = fps
        self.started_at = started_at
        self.received = 0
        self.dropped = 0
        self._queue: queue.Queue[_Frame | _End] = queue.Queue(maxsize=MAX_QUEUED_S * fps)
        self._done: asyncio.Future[EpisodeVideo | None] = asyncio.get_running_loop().create_future()
        self._thread = threading.Thread(target=self._run, name="video-encoder", daemon=True)
        self._thread.start()

    def add(self, timestamp: float, jpeg: bytes) -> None:
        """Queue one frame (returns at once)."""
        self.received += 1
        try:
            self._queue.put_nowait(_Frame(timestamp, jpeg))
        except queue.Full:
            self.dropped += 1

    def finish(self, ended_at: float) -> asyncio.Future[EpisodeVideo | None]:
        """End the video at ``ended_at`` (wall clock), at once; the future is its encoding, done once the thread
        has encoded the queued frames: None when no frame came or encoding failed (logged: a lost video never
        fails an episode)."""
        self._queue.put(_End(ended_at))
        return self._done

    def _run(self) -> None:
        with contextlib.suppress(OSError):  # a thread's own niceness (Linux): background work
            os.setpriority(os.PRIO_PROCESS, threading.get_native_id(), ENCODER_NICENESS)
        loop = self._done.get_loop()
        try:
            video = self._encode()
        except Exception as exc:  # a video is an extra: its failure is logged, the episode goes on
            log.warning("episode video lost: %s: %s", type(exc).__name__, exc)
            video = None
        with contextlib.suppress(RuntimeError):  # the loop closed meanwhile: nobody waits
            loop.call_soon_threadsafe(_resolve, self._done, video)

    def _encode(self) -> EpisodeVideo | None:
        periods: FramePeriods[bytes] = FramePeriods(self.fps, self.started_at)
        output = _Output(self.fps)
        duration_s = 0.0
        try:
            while True:
                item = self._queue.get()
                if isinstance(item, _End):
                    output.write_all(periods.end(item.timestamp))
                    duration_s = max(item.timestamp - self.started_at, output.last_period / self.fps)
                    break
                output.write_all(periods.add(item.timestamp, item.jpeg))
            if output.frames == 0:
                return None
            mp4 = output.close()
        finally:
            output.abandon()
        info = VideoInfo(
            started_at=self.started_at,
            fps=self.fps,
            duration_s=round(duration_s, 3),
            width=output.width,
            height=output.height,
            frames=output.frames,
            received=self.received,
            encode_cpu_s=round(time.thread_time(), 3),
        )
        return EpisodeVideo(mp4=mp4, info=info)


class _Output:
    """An MP4 being written in memory: opened at the first frame (whose size it takes)."""

    def __init__(self, fps: int) -> None:
        self.fps = fps
        self.frames = 0
        self.last_period = 0
        self.width = self.height = 0
        self._folder = tempfile.TemporaryDirectory(prefix="scratchworld-video-")
        self._path = Path(self._folder.name) / "video.mp4"
        """A file, not memory: ``faststart`` (the index first, so a page plays it before it has all of it) rewrites
        the file in a second pass, which a memory buffer cannot."""
        self._container: av.container.OutputContainer | None = None
        self._stream: av.VideoStream | None = None

    def write_all(self, frames: list[Timed[bytes]]) -> None:
        for timed in frames:
            self._write(timed)

    def _write(self, timed: Timed[bytes]) -> None:
        # Decoded by OpenCV to RGB: FFmpeg's JPEG decoder gives full-range YUV, whose conversion to the
        # video's limited range dithers every frame anew, and an editor's still areas then cost bits in
        # every frame (5.1 MB against 0.84 MB for the same 45 s episode).
        picture = cv2.imdecode(np.frombuffer(timed.item, np.uint8), cv2.IMREAD_COLOR)
        if picture is None:
            raise ValueError(f"a frame of {len(timed.item)} bytes is not a JPEG")
        height, width = picture.shape[:2]
        stream = self._stream or self._open(width, height)
        if (width, height) != (self.width, self.height):  # a resized page: scaled to the video's size
            picture = cv2.resize(picture, (self.width, self.height), interpolation=cv2.INTER_AREA)
        frame = av.VideoFrame.from_ndarray(picture, format="bgr24")
        frame.pts = timed.period
        frame.time_base = Fraction(1, self.fps)
        self._mux(stream.encode(frame))
        self.frames += 1
        self.last_period = timed.period

    def _open(self, width: int, height: int) -> av.VideoStream:
        self.width, self.height = width - width % 2, height - height % 2  # 4:2:0 needs even sizes
        self._container = av.open(str(self._path), mode="w", format="mp4", options={"movflags": "+faststart"})
        stream = self._container.add_stream("libx264", rate=self.fps)
        stream.width, stream.height, stream.pix_fmt = self.width, self.height, "yuv420p"
        stream.time_base = Fraction(1, self.fps)
        context = stream.codec_context
        context.options = {**X264_OPTIONS, "g": str(KEYFRAME_S * self.fps)}
        context.thread_count = 1  # two cores shared with browsers: one encoding thread is plenty at a few fps
        self._stream = stream
        return stream

    def _mux(self, packets: list[av.Packet]) -> None:
        if self._container is not None:
            for packet in packets:
                self._container.mux(packet)

    def close(self) -> bytes:
        """Flush the encoder and finish the file."""
        if self._stream is not None and self._container is not None:
            self._mux(self._stream.encode(None))
            self._container.close()
            self._container = None
        return self._path.read_bytes()

    def abandon(self) -> None:
        if self._container is not None:
            with contextlib.suppress(Exception):
                self._container.close()
            self._container = None
        self._folder.cleanup()


def _resolve(done: asyncio.Future[EpisodeVideo | None], video: EpisodeVideo | None) -> None:
    if not done.done():
        done.set_result(video)
