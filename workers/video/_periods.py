"""Which frames a video keeps: the newest of each frame period, shown from the period's start.

Frames come when the page changes, as often as Chromium composites (or as often as they are acknowledged);
a video of ``fps`` frames a second keeps, of the frames falling in one period of ``1/fps`` s on the wall
clock, the newest, at that period's presentation time. A period without a frame shows the frame before it
(the file holds no copy), so a still page costs nothing. The last frame is held until the end.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Generic, TypeVar

_T = TypeVar("_T")


@dataclass(frozen=True)
class Timed(Generic[_T]):
    """A kept frame and its presentation time, in periods since the video's start."""

    period: int
    item: _T


class FramePeriods(Generic[_T]):
    """Frames in, the frames a video keeps out (``add`` and ``end`` return those that are settled)."""

    def __init__(self, fps: int, started_at: float) -> None:
        """``started_at``: the wall-clock time (seconds) of the video's first instant."""
        self.fps = fps
        self.started_at = started_at
        self._pending: Timed[_T] | None = None
        self._last: Timed[_T] | None = None

    def period(self, timestamp: float) -> int:
        """The period a wall-clock time falls in (times before the start fall in the first)."""
        return max(0, math.floor((timestamp - self.started_at) * self.fps))

    def add(self, timestamp: float, item: _T) -> list[Timed[_T]]:
        """Take a frame; returns the frame of the period before, once a later period has begun."""
        period = self.period(timestamp)
        pending = self._pending
        if pending is not None and period <= pending.period:  # the same period (or a frame stamped late): newer
            self._pending = Timed(pending.period, item)
            return []
        self._pending = Timed(period, item)
        return [] if pending is None else [self._settle(pending)]

    def end(self, timestamp: float) -> list[Timed[_T]]:
        """The frames still held, and the last one again at ``timestamp``'s period, so the video lasts that long
        (nothing when no frame came at all)."""
        kept = [] if self._pending is None else [self._settle(self._pending)]
        self._pending = None
        last = self._last
        period = self.period(timestamp)
        if last is not None and period > last.period:
            kept.append(self._settle(Timed(period, last.item)))
        return kept

    def _settle(self, timed: Timed[_T]) -> Timed[_T]:
        self._last = timed
        return timed
