"""``first_difference`` on traces written by hand: the frame, target and field it names, and what it ignores."""

from __future__ import annotations

from typing import Any

from workers.evaluation import ObservableTrace, TraceDifference, TraceFrame, first_difference

SPRITE = {"x": 0, "y": 0, "direction": 90, "size": 100, "costume": "a", "visible": True, "effects": {}}
STAGE = {"costume": "backdrop1", "layers": ["Cat"], "var:v1": ["score", "0", False]}


def trace(
    *changes: tuple[int, dict[str, dict[str, Any]]] | tuple[int, dict[str, dict[str, Any]], list[str]], **extra: Any
) -> ObservableTrace:
    """Frame 0 (a stage and the sprite Cat), then ``(frame, {target: {field: value}}, [removed])`` changes."""
    frames = [TraceFrame(frame=0, targets={"Stage": dict(STAGE), "Cat": dict(SPRITE)})]
    for change in changes:
        frames.append(TraceFrame(frame=change[0], targets=change[1], removed=change[2] if len(change) > 2 else []))
    steps = max(frame.frame for frame in frames)
    return ObservableTrace(frames=frames, steps=extra.pop("steps", steps), chars=0, **extra)


def test_equal_traces_have_no_difference() -> None:
    a = trace((3, {"Cat": {"x": 10}}), (9, {"Cat": {"bubble": ["say", "hi"]}}))
    assert first_difference(a, a.model_copy()) is None


def test_the_same_change_a_frame_later_differs_in_the_earlier_frame() -> None:
    found = first_difference(trace((3, {"Cat": {"x": 10}})), trace((4, {"Cat": {"x": 10}})))
    assert found == TraceDifference(frame=3, target="Cat", field="x", a=10, b=0)
    assert found.describe() == "frame 3, Cat, x: 10 vs 0"


def test_a_run_that_ended_earlier_stays_as_it_ended() -> None:
    a = trace((3, {"Cat": {"x": 10}}))
    b = trace((3, {"Cat": {"x": 10}}), (40, {"Cat": {"y": 5}}))
    assert first_difference(a, b) == TraceDifference(frame=40, target="Cat", field="y", a=0, b=5)


def test_within_a_frame_the_stage_then_targets_by_key_then_fields_in_a_fixed_order_come_first() -> None:
    a = trace((2, {"Cat": {"bubble": ["say", "a"], "x": 1}, "Stage": {"costume": "night"}}))
    b = trace((2, {"Cat": {"bubble": ["say", "b"], "x": 2}}))
    assert first_difference(a, b) == TraceDifference(frame=2, target="Stage", field="costume", a="night", b="backdrop1")
    a = trace((2, {"Cat": {"bubble": ["say", "a"], "x": 1}}))
    assert first_difference(a, b) == TraceDifference(frame=2, target="Cat", field="x", a=1, b=2)


def test_a_clone_in_one_trace_only_is_a_difference_in_presence() -> None:
    clone = {"Cat#1": dict(SPRITE)}
    a = trace((5, clone), (9, {}, ["Cat#1"]))
    b = trace((5, clone), (8, {}, ["Cat#1"]))
    assert first_difference(a, b) == TraceDifference(frame=8, target="Cat#1", field="present", a=True, b=False)
    assert first_difference(a, trace()) == TraceDifference(frame=5, target="Cat#1", field="present", a=True, b=False)


def test_sounds_are_events_of_their_frame_also_from_a_clone_gone_in_it() -> None:
    a = trace((4, {"Cat#1": {"sounds": ["pop"]}}), (6, {"Cat": {"sounds": ["meow"]}}))
    b = trace((4, {"Cat#1": {"sounds": ["pop"]}}), (7, {"Cat": {"sounds": ["meow"]}}))
    assert first_difference(a, b) == TraceDifference(frame=6, target="Cat", field="sounds", a=["meow"], b=[])
    assert first_difference(a, a.model_copy()) is None


def test_variables_compare_by_id_values_always_names_only_where_a_monitor_shows_them() -> None:
    renamed = trace((2, {"Stage": {"var:v1": ["points", "3", False]}}))
    assert first_difference(trace((2, {"Stage": {"var:v1": ["score", "3", False]}})), renamed) is None
    found = first_difference(trace((2, {"Stage": {"var:v1": ["score", "4", False]}})), renamed)
    assert found == TraceDifference(frame=2, target="Stage", field="var:v1.value", a="4", b="3", variable="score")
    shown = first_difference(
        trace((2, {"Stage": {"var:v1": ["score", "3", True]}})),
        trace((2, {"Stage": {"var:v1": ["points", "3", True]}})),
    )
    assert shown is not None and (shown.field, shown.a, shown.b) == ("var:v1.name", "score", "points")


def test_a_variable_only_one_trace_has_counts_once_its_monitor_shows() -> None:
    helper = trace((1, {"Cat": {"var:h": ["helper", "1", False]}}), (6, {"Cat": {"var:h": ["helper", "6", False]}}))
    assert first_difference(trace(), helper) is None
    shown_later = trace((1, {"Cat": {"var:h": ["helper", "1", False]}}), (6, {"Cat": {"var:h": ["helper", "6", True]}}))
    found = first_difference(trace(), shown_later)
    assert found == TraceDifference(
        frame=6, target="Cat", field="var:h", a=None, b=["helper", "6", True], variable="helper"
    )


def test_a_truncated_trace_is_compared_only_as_far_as_it_was_recorded() -> None:
    whole = trace((3, {"Cat": {"x": 10}}), (30, {"Cat": {"x": 20}}))
    cut = trace((3, {"Cat": {"x": 10}}), truncated_at=30, steps=60)
    assert cut.truncated and not whole.truncated
    assert first_difference(whole, cut) is None
    assert first_difference(trace((3, {"Cat": {"x": 11}})), cut) == TraceDifference(
        frame=3, target="Cat", field="x", a=11, b=10
    )


def test_a_trace_reads_the_pages_json() -> None:
    page = {
        "frames": [{"frame": 0, "targets": {"Stage": STAGE}}, {"frame": 2, "targets": {}, "removed": ["Cat#1"]}],
        "steps": 3,
        "truncatedAt": None,
        "chars": 120,
    }
    read = ObservableTrace.model_validate(page)
    assert (read.steps, read.truncated, read.frames[1].removed) == (3, False, ["Cat#1"])
