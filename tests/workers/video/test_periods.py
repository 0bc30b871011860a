"""Which screencast frames a video keeps: the newest of each frame period, the last one held to the end."""

from __future__ import annotations

from workers.video import FramePeriods, Timed


def kept(fps: int, frames: list[tuple[float, str]], end: float) -> list[tuple[int, str]]:
    periods: FramePeriods[str] = FramePeriods(fps, started_at=100.0)
    out: list[Timed[str]] = []
    for timestamp, name in frames:
        out += periods.add(timestamp, name)
    out += periods.end(end)
    return [(timed.period, timed.item) for timed in out]


def test_the_newest_frame_of_each_period_is_kept_at_the_period_s_start() -> None:
    frames = [(100.01, "a"), (100.05, "b"), (100.19, "c"), (100.21, "d"), (100.9, "e")]
    assert kept(5, frames, end=101.0) == [(0, "c"), (1, "d"), (4, "e"), (5, "e")]


def test_a_still_page_costs_one_frame_held_until_the_end() -> None:
    assert kept(5, [(100.0, "only")], end=160.0) == [(0, "only"), (300, "only")]


def test_no_frame_no_video_and_an_end_inside_the_last_period_adds_none() -> None:
    assert kept(5, [], end=105.0) == []
    assert kept(2, [(100.1, "a"), (100.6, "b")], end=100.9) == [(0, "a"), (1, "b")]


def test_frames_stamped_before_the_start_or_out_of_order_never_go_back_in_time() -> None:
    frames = [(99.5, "early"), (100.5, "b"), (100.3, "late")]
    assert kept(10, frames, end=100.55) == [(0, "early"), (5, "late")]
