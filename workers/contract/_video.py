"""Episode video: whether an episode is recorded, and the recording a worker returns.

A video is what a person watches, never what is judged: it is not part of a job's identity, and recording
one changes no step, no page time and no verdict (the frames are the compositor's, taken on the wall clock).
"""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field


class RecordSettings(BaseModel):
    """What of an episode is recorded besides its steps (the sweep's ``record:``, ``replay --video``)."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    video: bool = False
    """Record the agent's editor as an H.264 MP4 (``video.mp4`` among the attempt's artifacts)."""

    fps: int = Field(default=5, ge=1, le=30)
    """Frames per second of the video at most (the page is sent and encoded no more often; a still page
    costs no frames at all)."""

    width: int = Field(default=1280, ge=320, le=1280)
    """The video's width in pixels (its height follows the page's 16:9): a smaller file, not a cheaper recording
    (Chromium copies every changed frame whatever the size; 640 cost what 1280 did, see docs/video.md)."""


class VideoInfo(BaseModel):
    """A recording's facts, kept beside it (``video.json``): how to line the video up with the steps."""

    model_config = ConfigDict(frozen=True)

    started_at: float
    """The wall-clock time (seconds since the epoch, the worker's clock) of the video's first instant:
    a step that began at ``StepRecord.started_at`` is at ``started_at - this`` seconds into the video."""

    fps: int
    duration_s: float
    width: int
    height: int
    frames: int
    """Frames in the file (a still page between two changes is one frame)."""

    received: int
    """Frames Chromium sent (at most ``fps`` a second; the newest of each frame period is kept)."""

    encode_cpu_s: float
    """CPU seconds the encoding took on the worker (a thread of its own, off the event loop)."""


class EpisodeVideo(BaseModel):
    """The video of an episode, as a worker returns it with the job's result."""

    model_config = ConfigDict(frozen=True)

    mp4: bytes = Field(repr=False)
    info: VideoInfo
