"""The steps' marks on an episode video's timeline: placed by their wall-clock start, drawn as they were done."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from scratchworld_dist.viewer._video import MARK_HOLD_S, video_marks, video_view
from workers.contract import StepRecord, VideoInfo

INFO = VideoInfo(
    started_at=1_000.0, fps=5, duration_s=20.0, width=1280, height=720, frames=40, received=50, encode_cpu_s=0.5
)


def step(index: int, at: float | None, action: str, **fields: object) -> StepRecord:
    return StepRecord.model_validate({"index": index, "action": action, "ok": True, "started_at": at, **fields})


def test_each_step_shows_from_its_start_until_the_next_one_with_what_it_did() -> None:
    steps = [
        step(0, 1_001.0, "click", data={"x": 100.5, "y": 200}),
        step(1, 1_003.5, "drag_and_drop", data={"start": [10, 20], "end": [300, 400], "snapped": True}),
        step(2, 1_006.0, "type", args={"text": "hello <world>"}, data={"typed": 13}),
        step(3, 1_007.0, "hotkey", data={"keys": ["Control", "a"]}),
        step(4, 1_009.0, "add_block", args={"blockType": "motion_movesteps"}, ok=False),
        step(5, 1_010.0, "done", latency_s=0.5),
    ]
    marks = video_marks(INFO, steps)
    assert [(m.index, m.start_s, m.end_s) for m in marks] == [
        (0, 1.0, 3.5),
        (1, 3.5, 6.0),
        (2, 6.0, 7.0),
        (3, 7.0, 9.0),
        (4, 9.0, 10.0),
        (5, 10.0, 10.0 + 0.5 + MARK_HOLD_S),
    ]
    click, drag, typed, keys, composite, done = marks
    assert (click.label, click.point) == ("#0 click", (100.5, 200))
    assert (drag.path, drag.snapped) == ((10, 20, 300, 400), True)
    assert typed.text == "typed “hello <world>”"
    assert keys.text == "keys Control+a"
    assert (composite.text, composite.ok) == ('{"blockType": "motion_movesteps"}', False)
    assert done.text is None and done.point is None


def test_steps_without_a_wall_clock_start_are_left_off() -> None:
    marks = video_marks(INFO, [step(0, None, "click", data={"x": 1, "y": 2}), step(1, 1_002.0, "done")])
    assert [m.index for m in marks] == [1]


def test_the_page_gets_the_video_and_its_marks_as_json_that_cannot_end_its_script(tmp_path: Path) -> None:
    assert video_view(tmp_path, "job/attempt-1", []) is None  # no video.mp4: nothing shown
    (tmp_path / "video.mp4").write_bytes(b"\x00")
    assert video_view(tmp_path, "job/attempt-1", []) is None  # no video.json: it cannot be lined up
    (tmp_path / "video.json").write_text(INFO.model_dump_json())
    steps = [step(0, 1_002.0, "type", args={"text": "</script><b>"})]
    view = video_view(tmp_path, "job/attempt-1", steps)
    assert view is not None
    assert view.href == "../files/job/attempt-1/video.mp4"
    assert "<" not in view.marks_json
    assert json.loads(view.marks_json) == [
        {
            "index": 0,
            "start_s": 2.0,
            "end_s": pytest.approx(3.5),
            "label": "#0 type",
            "ok": True,
            "text": "typed “</script><b>”",
        }
    ]
