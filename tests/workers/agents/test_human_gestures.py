"""A person's raw input coalesced into primitive steps: each step is one complete gesture, in the arguments the
gestures of a model's episode take, so a person's trajectory replays and reads like a model's."""

from __future__ import annotations

from workers.agents._human import GestureRecorder, KeyEvent, MouseEvent, WheelEvent
from workers.agents._human._recorder import DOUBLE_CLICK_S, TYPING_IDLE_S
from workers.contract import PrimitiveAction
from workers.primitive._gestures import DragArgs, HotkeyArgs, KeyArgs, PointArgs, ScrollArgs, TypeArgs

ARGS = {
    "click": PointArgs,
    "double_click": PointArgs,
    "drag_and_drop": DragArgs,
    "scroll": ScrollArgs,
    "type": TypeArgs,
    "key": KeyArgs,
    "hotkey": HotkeyArgs,
}


def mouse(event: str, x: float, y: float, **fields: object) -> MouseEvent:
    return MouseEvent.model_validate({"event": event, "x": x, "y": y, **fields})


def key(name: str, **modifiers: bool) -> KeyEvent:
    return KeyEvent(event="down", key=name, **modifiers)


def steps(recorder: GestureRecorder, *timed: tuple[float, MouseEvent | KeyEvent | WheelEvent]) -> list[PrimitiveAction]:
    done = [action for at, event in timed for action in recorder.feed(event, at)]
    done += recorder.flush()
    for action in done:  # every step is valid input for the gestures of a model's episode
        ARGS[action.api].model_validate(action.args)
    return done


def test_a_press_and_release_in_place_is_a_click_once_no_second_press_follows() -> None:
    recorder = GestureRecorder()
    assert recorder.feed(mouse("down", 100, 50), 0.0) == []
    assert recorder.feed(mouse("move", 102, 51, buttons=1), 0.05) == []  # within the drag threshold
    assert recorder.feed(mouse("up", 102, 51), 0.1) == []  # a double click may still come
    assert recorder.next_deadline() == 0.1 + DOUBLE_CLICK_S
    assert recorder.due(0.2) == []
    (click,) = recorder.due(0.1 + DOUBLE_CLICK_S)
    assert (click.api, click.args) == ("click", {"x": 100.0, "y": 50.0})
    assert recorder.next_deadline() is None


def test_a_second_press_makes_a_double_click_and_another_button_its_own_click() -> None:
    done = steps(
        GestureRecorder(),
        (0.0, mouse("down", 10, 10)),
        (0.05, mouse("up", 10, 10)),
        (0.15, mouse("down", 11, 10, clicks=2)),
        (0.2, mouse("up", 11, 10, clicks=2)),
        (1.0, mouse("down", 300, 200, button="right")),
        (1.1, mouse("up", 300, 200, button="right")),
    )
    assert [(a.api, a.args) for a in done] == [
        ("double_click", {"x": 10.0, "y": 10.0}),
        ("click", {"x": 300.0, "y": 200.0, "button": "right"}),
    ]


def test_a_press_that_moves_is_a_drag_from_the_press_to_the_release() -> None:
    (drag,) = steps(
        GestureRecorder(),
        (1.0, mouse("down", 100.04, 200)),
        (1.1, mouse("move", 150, 220, buttons=1)),
        (1.6, mouse("move", 300, 260, buttons=1)),
        (1.75, mouse("up", 301, 261)),
    )
    assert drag.api == "drag_and_drop"
    assert drag.args == {"start_x": 100.0, "start_y": 200.0, "end_x": 301.0, "end_y": 261.0, "duration": 0.75}


def test_typing_gathers_characters_until_another_key_or_a_pause() -> None:
    recorder = GestureRecorder()
    done = steps(
        recorder,
        (0.0, mouse("down", 50, 50)),
        (0.05, mouse("up", 50, 50)),
        (0.1, key("H", shift=True)),
        (0.2, key("i")),
        (0.3, key(" ")),
        (0.4, KeyEvent(event="down", key="Shift")),  # a modifier alone is no step
        (0.5, key("Backspace")),
        (0.55, key("Dead")),  # a key no gesture could press again (an accent's dead key): no step
        (0.6, key("a", ctrl=True)),
        (0.7, key("x")),
        (0.7 + TYPING_IDLE_S, key("y")),  # a pause ends the typed run
    )
    assert [(a.api, a.args) for a in done] == [
        ("click", {"x": 50.0, "y": 50.0}),  # typing completes a click waiting for a second press
        ("type", {"text": "Hi "}),
        ("key", {"key": "Backspace"}),
        ("hotkey", {"keys": ["ctrl", "a"]}),
        ("type", {"text": "x"}),
        ("type", {"text": "y"}),
    ]


def test_wheel_turns_at_one_place_are_one_scroll() -> None:
    done = steps(
        GestureRecorder(),
        (0.0, WheelEvent(x=500, y=300, dx=0, dy=100)),
        (0.05, WheelEvent(x=502, y=301, dx=0, dy=60)),
        (0.1, WheelEvent(x=900, y=300, dx=-40, dy=0)),  # elsewhere: another scroll
        (0.15, key("Enter")),
    )
    assert [(a.api, a.args) for a in done] == [
        ("scroll", {"direction": "down", "amount": 160, "x": 500.0, "y": 300.0}),
        ("scroll", {"direction": "left", "amount": 40, "x": 900.0, "y": 300.0}),
        ("key", {"key": "Enter"}),
    ]
