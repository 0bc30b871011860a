"""Raw input coalesced into the steps a model's episode is made of: click, double_click, drag_and_drop,
scroll, type, key and hotkey, with the arguments ``workers.primitive.Gestures`` takes.

A press and release within ``DRAG_THRESHOLD_PX`` is a click, farther a drag from the press to the release;
a click waits ``DOUBLE_CLICK_S`` for a second one that makes it a double click; wheel turns at one place and
characters typed in a row gather until something else happens or they pause (``SCROLL_IDLE_S``,
``TYPING_IDLE_S``). A gesture is a step once it is complete, so a step never holds half a gesture.
"""

from __future__ import annotations

import math

from pydantic import JsonValue

from workers.agents._human._events import MODIFIER_KEYS, InputEvent, KeyEvent, MouseEvent, WheelEvent
from workers.contract import PrimitiveAction
from workers.primitive._gestures import GestureError, key_name

DRAG_THRESHOLD_PX = 4.0
"""A press that moves farther than this before its release is a drag (what Blockly takes for one is 3)."""

DOUBLE_CLICK_S = 0.4
TYPING_IDLE_S = 1.5
SCROLL_IDLE_S = 0.4
MAX_DRAG_S = 10.0
"""The longest ``drag_and_drop`` duration the schema takes; a slower drag is recorded at this."""

SCROLL_SPAN_PX = 8.0
"""Wheel turns within this distance of the first one belong to one scroll."""


def _point(x: float, y: float) -> tuple[float, float]:
    return round(x, 1), round(y, 1)


class _Press:
    def __init__(self, event: MouseEvent, now: float, double: bool) -> None:
        self.start = _point(event.x, event.y)
        self.button = event.button
        self.at = now
        self.double = double
        self.moved = False


class GestureRecorder:
    """Feed it the person's raw events with the time they arrived; it answers the completed gestures, in order."""

    def __init__(self) -> None:
        self._press: _Press | None = None
        self._click: tuple[PrimitiveAction, float] | None = None
        """A click waiting to see whether a second press makes it a double click, with its deadline."""
        self._scroll: tuple[tuple[float, float], float, float, float] | None = None
        """Where a scroll began, its summed dx and dy, and its deadline."""
        self._typed: tuple[str, float] | None = None

    def feed(self, event: InputEvent, now: float) -> list[PrimitiveAction]:
        done = self.due(now)
        if isinstance(event, MouseEvent):
            done += self._mouse(event, now)
        elif isinstance(event, WheelEvent):
            done += self._wheel(event, now)
        elif event.event == "down" and event.key not in MODIFIER_KEYS:
            done += self._key(event, now)
        return done

    def due(self, now: float) -> list[PrimitiveAction]:
        """The gestures whose wait for more input is over."""
        done = []
        if self._click is not None and self._click[1] <= now:
            done.append(self._click[0])
            self._click = None
        if self._scroll is not None and self._scroll[3] <= now:
            done += self._end_scroll()
        if self._typed is not None and self._typed[1] <= now:
            done += self._end_typing()
        return done

    def next_deadline(self) -> float | None:
        """When the next waiting gesture is complete by itself (None: none waits)."""
        waits = [wait[-1] for wait in (self._click, self._scroll, self._typed) if wait is not None]
        return min(waits) if waits else None

    def flush(self) -> list[PrimitiveAction]:
        """Every gesture still waiting, complete as it is (the person submitted or gave up)."""
        done = [self._click[0]] if self._click is not None else []
        self._click = None
        return done + self._end_scroll() + self._end_typing()

    def _others(self, keep_click: bool = False) -> list[PrimitiveAction]:
        """Gestures another kind of input completes (a pending click waits for a possible second press)."""
        done = [] if keep_click or self._click is None else [self._click[0]]
        if not keep_click:
            self._click = None
        return done + self._end_scroll() + self._end_typing()

    def _mouse(self, event: MouseEvent, now: float) -> list[PrimitiveAction]:
        if event.event == "down":
            double = event.clicks >= 2 and self._click is not None and self._near(self._click[0], event)
            first = self._click[0].args if double and self._click is not None else None
            done = self._others(keep_click=double)
            self._click = None
            self._press = _Press(event, now, double)
            if first is not None:  # a double click is where its first click was
                self._press.start = (float(first["x"]), float(first["y"]))  # type: ignore[arg-type]
            return done
        press = self._press
        if press is None:
            return []
        if math.dist(press.start, (event.x, event.y)) > DRAG_THRESHOLD_PX:
            press.moved = True
        if event.event == "move":
            return []
        self._press = None
        end = _point(event.x, event.y)
        if press.moved and press.button == "left":
            duration = round(min(max(now - press.at, 0.0), MAX_DRAG_S), 2)
            args: dict[str, JsonValue] = {
                "start_x": press.start[0], "start_y": press.start[1], "end_x": end[0], "end_y": end[1],
                "duration": duration,
            }  # fmt: skip
            return [PrimitiveAction(api="drag_and_drop", args=args)]
        x, y = press.start
        if press.double:
            return [PrimitiveAction(api="double_click", args={"x": x, "y": y})]
        if press.button != "left":
            return [PrimitiveAction(api="click", args={"x": x, "y": y, "button": press.button})]
        self._click = (PrimitiveAction(api="click", args={"x": x, "y": y}), now + DOUBLE_CLICK_S)
        return []

    @staticmethod
    def _near(click: PrimitiveAction, event: MouseEvent) -> bool:
        x, y = click.args["x"], click.args["y"]
        if not isinstance(x, float) or not isinstance(y, float):
            return False
        return math.dist((x, y), (event.x, event.y)) <= DRAG_THRESHOLD_PX

    def _wheel(self, event: WheelEvent, now: float) -> list[PrimitiveAction]:
        done = [*self._pending_click(), *self._end_typing()]
        if self._scroll is not None and math.dist(self._scroll[0], (event.x, event.y)) > SCROLL_SPAN_PX:
            done += self._end_scroll()
        if self._scroll is None:
            self._scroll = (_point(event.x, event.y), 0.0, 0.0, 0.0)
        at, dx, dy, _ = self._scroll
        self._scroll = (at, dx + event.dx, dy + event.dy, now + SCROLL_IDLE_S)
        return done

    def _pending_click(self) -> list[PrimitiveAction]:
        done = [self._click[0]] if self._click is not None else []
        self._click = None
        return done

    def _end_scroll(self) -> list[PrimitiveAction]:
        if self._scroll is None:
            return []
        (x, y), dx, dy, _ = self._scroll
        self._scroll = None
        if abs(dy) >= abs(dx):
            direction, amount = ("down" if dy > 0 else "up"), abs(dy)
        else:
            direction, amount = ("right" if dx > 0 else "left"), abs(dx)
        if round(amount) < 1:
            return []
        args: dict[str, JsonValue] = {"direction": direction, "amount": min(round(amount), 5000), "x": x, "y": y}
        return [PrimitiveAction(api="scroll", args=args)]

    def _key(self, event: KeyEvent, now: float) -> list[PrimitiveAction]:
        chord = event.ctrl or event.alt or event.meta
        if len(event.key) == 1 and not chord:  # a character (shift gives its capital): part of typing
            typed = self._typed[0] if self._typed is not None else ""
            done = [*self._pending_click(), *self._end_scroll()]
            self._typed = (typed + event.key, now + TYPING_IDLE_S)
            return done
        done = self._others()
        if len(event.key) > 1 and not _replayable(event.key):
            return done  # a key no gesture can press again (Dead, Unidentified, media keys): relayed, not a step
        modifiers = [name for name, held in (("ctrl", event.ctrl), ("alt", event.alt), ("meta", event.meta)) if held]
        if event.shift and (chord or len(event.key) > 1):
            modifiers.append("shift")
        key = event.key.lower() if len(event.key) == 1 else event.key
        if modifiers:
            keys: list[JsonValue] = [*modifiers, key]
            return [*done, PrimitiveAction(api="hotkey", args={"keys": keys})]
        return [*done, PrimitiveAction(api="key", args={"key": key})]

    def _end_typing(self) -> list[PrimitiveAction]:
        if self._typed is None:
            return []
        text, _ = self._typed
        self._typed = None
        return [PrimitiveAction(api="type", args={"text": text})]


def _replayable(key: str) -> bool:
    """Whether a ``key`` or ``hotkey`` step could press ``key`` again."""
    try:
        key_name(key)
    except GestureError:
        return False
    return True
