"""A page's screencast (``workers.editor.Screencast``): frames as Chromium composites them, each acknowledged and
stamped on the wall clock, no more often than asked, and none after it stops; ``replay --video`` records with it."""

from __future__ import annotations

import asyncio
import io
import itertools
import time
from pathlib import Path

import av
import cv2
import numpy as np
import pytest

from tests.conftest import SUITE_DIR, pooled_editor
from tests.support.cli_runner import invoke
from workers.editor import EditorPool, Screencast, ScreencastFrame

pytestmark = pytest.mark.browser


async def test_frames_come_while_the_page_changes_stamped_on_the_wall_clock(shared_pool: EditorPool) -> None:
    frames: list[ScreencastFrame] = []
    async with pooled_editor(shared_pool) as editor:
        await editor.resume()  # a stepping VM redraws its stage: the page changes all the time
        before = time.time()
        async with Screencast(editor.page, frames.append, max_fps=10) as screencast:
            async with asyncio.timeout(60):
                while len(frames) < 10:  # more than the few Chromium sends before the first acknowledgements
                    await editor.page.mouse.move(100 + 10 * len(frames), 300)
                    await asyncio.sleep(0.05)
            last = await screencast.capture()
        after = time.time()
        count = len(frames)
        await editor.page.mouse.move(400, 400)
        await editor.page.evaluate("() => new Promise((done) => requestAnimationFrame(() => done(null)))")
    assert len(frames) == count  # stopped: no frame after
    assert screencast.frames == count
    stamps = [frame.timestamp for frame in frames]
    assert all(before - 1 <= stamp <= after for stamp in stamps)
    # Frames in flight together are encoded side by side and may arrive a frame apart, not more.
    assert all(later >= earlier - 0.1 for earlier, later in itertools.pairwise(stamps))
    # At most max_fps once going (a load only spaces them further): acknowledgements come no sooner than
    # 1/max_fps after the one before, and Chromium keeps two frames unacknowledged, so a frame is made after
    # the acknowledgement of the one two before it. Two may come close together (seen under load: a pair
    # 0.03 s apart), but the last 7 span at least 4 gaps.
    assert max(stamps) - sorted(stamps)[-7] >= 0.4
    picture = cv2.imdecode(np.frombuffer(frames[-1].jpeg, np.uint8), cv2.IMREAD_COLOR)
    assert picture.shape == (720, 1280, 3) and (frames[-1].width, frames[-1].height) == (1280, 720)
    assert cv2.imdecode(np.frombuffer(last.jpeg, np.uint8), cv2.IMREAD_COLOR).shape == (720, 1280, 3)


@pytest.mark.slow
def test_replay_records_the_editor_as_a_video(tmp_path: Path) -> None:
    video = tmp_path / "replay.mp4"
    done = invoke("replay", str(SUITE_DIR), "bouncing_ball_stuck", "--video", str(video), "--fps", "4")
    assert done.returncode == 0, done.stdout + done.stderr
    assert f"video: {video}" in " ".join(done.stdout.split())
    container = av.open(io.BytesIO(video.read_bytes()))
    assert container.streams.video[0].codec_context.name == "h264"
    times = [float(frame.time) for frame in container.decode(video=0)]
    assert len(times) >= 2 and times == sorted(times)
    assert all(round(t * 4, 6).is_integer() for t in times)  # on the 4 fps grid
