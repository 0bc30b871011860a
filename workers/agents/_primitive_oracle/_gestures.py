"""The primitive actions the oracle hands out, built from page points (``Gestures`` performs them)."""

from __future__ import annotations

from workers.agents._primitive_oracle._geometry import Point
from workers.contract import PrimitiveAction

DRAG_DURATION = 0.3
DRAG_STEPS = max(10, int(DRAG_DURATION * 30))
"""Mouse moves of one drag: the rule of ``Gestures`` (30 per second of duration, at least 10)."""


def click(at: Point) -> PrimitiveAction:
    return PrimitiveAction(api="click", args={"x": round(at.x, 2), "y": round(at.y, 2)})


def drag(start: Point, end: Point) -> PrimitiveAction:
    return PrimitiveAction(
        api="drag_and_drop",
        args={
            "start_x": round(start.x, 2),
            "start_y": round(start.y, 2),
            "end_x": round(end.x, 2),
            "end_y": round(end.y, 2),
            "duration": DRAG_DURATION,
        },
    )


def scroll(dy: float, dx: float, at: Point) -> PrimitiveAction:
    """A wheel turn at ``at`` that moves the content under it up by ``dy`` and left by ``dx`` pixels."""
    if abs(dy) >= abs(dx):
        direction, amount = ("down" if dy > 0 else "up"), abs(dy)
    else:
        direction, amount = ("right" if dx > 0 else "left"), abs(dx)
    return PrimitiveAction(
        api="scroll",
        args={"direction": direction, "amount": max(1, round(amount)), "x": round(at.x, 2), "y": round(at.y, 2)},
    )


def fmt(point: Point) -> str:
    """A point in messages: ``(x, y)`` in whole pixels."""
    return f"({point.x:.0f}, {point.y:.0f})"
