"""What crosses the person's websocket: raw input in editor pixels and their decisions (in), the task, the
episode's progress and its end (out).

Raw events are relayed to the editor as they come (``_relay``) and coalesced into the steps of the
primitive action schema (``_recorder``); both read these models, validated at the socket.
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field

Button = Literal["left", "right", "middle"]


class _Event(BaseModel):
    model_config = ConfigDict(frozen=True, extra="ignore")


class MouseEvent(_Event):
    """A button pressed or released, or the pointer moved, at (x, y) of the editor's viewport."""

    type: Literal["mouse"] = "mouse"
    event: Literal["down", "up", "move"]
    x: float
    y: float
    button: Button = "left"
    buttons: int = Field(default=0, ge=0)
    """The buttons held (the DOM's bit mask): moves while one is held are part of a drag, never dropped."""

    clicks: int = Field(default=1, ge=1, le=3)
    """The DOM's ``detail``: 2 on the second press of a double click."""


class WheelEvent(_Event):
    """A wheel turn at (x, y), in pixels."""

    type: Literal["wheel"] = "wheel"
    x: float
    y: float
    dx: float
    dy: float


class KeyEvent(_Event):
    """A key pressed or released; ``key`` is the DOM's ``KeyboardEvent.key`` (``a``, ``A``, ``Enter``...)."""

    type: Literal["key"] = "key"
    event: Literal["down", "up"]
    key: str = Field(min_length=1, max_length=40)
    ctrl: bool = False
    alt: bool = False
    meta: bool = False
    shift: bool = False


class Decision(_Event):
    """The person is finished: they submit the project as it is, or give up."""

    type: Literal["submit", "give_up"]


class TaskShown(BaseModel):
    """The first message a page gets: what to do, and how to map its picture to the editor's pixels."""

    model_config = ConfigDict(frozen=True)

    type: Literal["task"] = "task"
    task_id: str
    instruction: str
    mode: str
    max_steps: int
    participant: str
    started_at: float
    """When the episode started (epoch seconds): the page's timer counts from it."""

    viewport: dict[str, int]


class Progress(BaseModel):
    """Steps recorded so far; ``ready``: the harness has observed the editor and waits for the next gesture."""

    model_config = ConfigDict(frozen=True)

    type: Literal["status"] = "status"
    steps: int = 0
    ready: bool = False


class Ended(BaseModel):
    """The episode is over (``reason``: its stop reason: done, failed, max_steps, an error class)."""

    model_config = ConfigDict(frozen=True)

    type: Literal["ended"] = "ended"
    reason: str
    steps: int


PageMessage = Annotated[MouseEvent | WheelEvent | KeyEvent | Decision, Field(discriminator="type")]
InputEvent = MouseEvent | WheelEvent | KeyEvent

MODIFIER_KEYS = frozenset({"Shift", "Control", "Alt", "Meta", "AltGraph", "CapsLock"})
"""Keys that are held with others: relayed, never a step of their own."""
