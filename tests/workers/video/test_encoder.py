"""Encoding screencast frames as H.264 MP4 in a thread: a file a browser plays, on the frames' wall clock."""

from __future__ import annotations

import io
import threading

import av
import cv2
import numpy as np
import pytest

from workers.video import VideoEncoder


def jpeg(number: int, size: tuple[int, int] = (640, 360)) -> bytes:
    picture = np.full((size[1], size[0], 3), 255, np.uint8)
    cv2.putText(picture, f"frame {number}", (40, 200), cv2.FONT_HERSHEY_SIMPLEX, 2, (40, 40, 40), 4)
    ok, data = cv2.imencode(".jpg", picture)
    assert ok
    return data.tobytes()


async def test_frames_become_an_h264_mp4_timed_on_the_wall_clock() -> None:
    start = 1_000.0
    encoder = VideoEncoder(fps=5, started_at=start)
    for number in range(10):  # 10 frames a second for one second: the newest of each 0.2 s is kept
        encoder.add(start + number * 0.1 + 0.01, jpeg(number))
    encoder.add(start + 3.05, jpeg(99))  # then a still page until one change at 3.05 s
    video = await encoder.finish(start + 6.0)
    assert video is not None
    info = video.info
    assert (info.fps, info.width, info.height, info.received) == (5, 640, 360, 11)
    assert info.frames == 7  # 5 periods of the first second, the change, and the last frame held to the end
    assert info.duration_s == pytest.approx(6.0)
    assert info.encode_cpu_s > 0

    container = av.open(io.BytesIO(video.mp4))
    stream = container.streams.video[0]
    assert stream.codec_context.name == "h264"
    times = [float(frame.time) for frame in container.decode(video=0)]
    assert times == pytest.approx([0.0, 0.2, 0.4, 0.6, 0.8, 3.0, 6.0])
    assert container.duration is not None and container.duration / 1e6 == pytest.approx(6.2)


async def test_a_resized_page_is_scaled_to_the_video_s_size() -> None:
    encoder = VideoEncoder(fps=2, started_at=0.0)
    encoder.add(0.1, jpeg(1, (640, 360)))
    encoder.add(0.9, jpeg(2, (1280, 720)))
    video = await encoder.finish(1.0)
    assert video is not None
    frames = list(av.open(io.BytesIO(video.mp4)).decode(video=0))
    assert [(f.width, f.height) for f in frames] == [(640, 360)] * 3  # the last one held to the end


async def test_no_frame_or_a_broken_one_gives_no_video_and_no_error() -> None:
    assert await VideoEncoder(fps=5, started_at=0.0).finish(1.0) is None
    broken = VideoEncoder(fps=5, started_at=0.0)
    broken.add(0.1, b"not a jpeg")
    assert await broken.finish(1.0) is None


async def test_the_encoding_runs_in_a_thread_of_its_own_that_ends_with_the_video() -> None:
    encoder = VideoEncoder(fps=5, started_at=0.0)
    worker = next(thread for thread in threading.enumerate() if thread.name == "video-encoder" and thread.is_alive())
    assert worker is not threading.current_thread()
    encoder.add(0.1, jpeg(1))
    assert await encoder.finish(0.5) is not None
    worker.join(timeout=10)
    assert not worker.is_alive()
