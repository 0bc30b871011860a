"""Low-level GUI actions carried out with Playwright's real mouse and keyboard.

Arguments arrive as the agent wrote them and are checked here, so every mistake (both an index
and coordinates, a point outside the viewport, an index the latest element list does not have,
an unknown key) becomes an error envelope that costs the agent a step instead of crashing it.
"""

from __future__ import annotations

import re
import time
from collections.abc import Awaitable, Callable, Sequence
from typing import Literal, Protocol

from playwright.async_api import Error as PlaywrightError
from playwright.async_api import Page
from pydantic import BaseModel, ConfigDict, Field, JsonValue, ValidationError, model_validator

from workers.contract import ActionEnvelope
from workers.primitive._pressed_moves import pressed_moves

PRIMITIVE_APIS = ("click", "double_click", "drag_and_drop", "scroll", "type", "key", "hotkey")
"""The gestures an agent may use besides ``done`` and ``failed``."""


class Located(Protocol):
    """What an index resolves against: an element of the latest observation's list."""

    @property
    def center(self) -> tuple[float, float]: ...


class GestureError(Exception):
    """An action the environment refuses; becomes an error envelope with ``code``."""

    def __init__(self, code: str, message: str) -> None:
        super().__init__(message)
        self.code = code


class _Args(BaseModel):
    model_config = ConfigDict(frozen=True, extra="forbid")


def _one_target(x: float | None, y: float | None, index: int | None, what: str) -> None:
    has_point = x is not None or y is not None
    if has_point and index is not None:
        raise ValueError(f"give either {what}x and {what}y or {what}index, not both")
    if index is None and (x is None or y is None):
        raise ValueError(f"give {what}x and {what}y, or {what}index")


class PointArgs(_Args):
    """Arguments of click and double_click."""

    x: float | None = None
    y: float | None = None
    index: int | None = Field(default=None, ge=0)
    button: Literal["left", "right", "middle"] = "left"

    @model_validator(mode="after")
    def _target(self) -> PointArgs:
        _one_target(self.x, self.y, self.index, "")
        return self


class DragArgs(_Args):
    start_x: float | None = None
    start_y: float | None = None
    start_index: int | None = Field(default=None, ge=0)
    end_x: float | None = None
    end_y: float | None = None
    end_index: int | None = Field(default=None, ge=0)
    duration: float = Field(default=0.5, ge=0, le=10)
    """Seconds of movement, turned into interpolated mouse moves (30 per second, at least 10)."""

    @model_validator(mode="after")
    def _targets(self) -> DragArgs:
        _one_target(self.start_x, self.start_y, self.start_index, "start_")
        _one_target(self.end_x, self.end_y, self.end_index, "end_")
        return self


class ScrollArgs(_Args):
    direction: Literal["up", "down", "left", "right"]
    amount: int = Field(default=100, ge=1, le=5000)
    x: float | None = None
    y: float | None = None
    index: int | None = Field(default=None, ge=0)

    @model_validator(mode="after")
    def _target(self) -> ScrollArgs:
        if self.x is not None or self.y is not None or self.index is not None:
            _one_target(self.x, self.y, self.index, "")
        return self


class TypeArgs(_Args):
    text: str = Field(max_length=10_000)


class KeyArgs(_Args):
    key: str = Field(min_length=1, max_length=40)


class HotkeyArgs(_Args):
    keys: list[str] = Field(min_length=1, max_length=5)
    """Modifiers then the key, e.g. ``["ctrl", "a"]``; ``"ctrl+a"`` is accepted too."""

    @model_validator(mode="before")
    @classmethod
    def _split(cls, data: object) -> object:
        if isinstance(data, dict) and isinstance(data.get("keys"), str):
            return {**data, "keys": [part for part in data["keys"].split("+") if part]}
        return data


_KEY_ALIASES = {
    "ctrl": "Control", "control": "Control", "cmd": "Meta", "command": "Meta", "meta": "Meta", "win": "Meta",
    "alt": "Alt", "option": "Alt", "shift": "Shift", "enter": "Enter", "return": "Enter", "esc": "Escape",
    "escape": "Escape", "tab": "Tab", "space": "Space", " ": "Space", "backspace": "Backspace", "delete": "Delete",
    "del": "Delete", "insert": "Insert", "home": "Home", "end": "End", "pageup": "PageUp", "pagedown": "PageDown",
    "up": "ArrowUp", "down": "ArrowDown", "left": "ArrowLeft", "right": "ArrowRight", "arrowup": "ArrowUp",
    "arrowdown": "ArrowDown", "arrowleft": "ArrowLeft", "arrowright": "ArrowRight", "capslock": "CapsLock",
}  # fmt: skip
_NAMED_KEY = re.compile(r"^(F([1-9]|1[0-9]|2[0-4])|Key[A-Z]|Digit[0-9])$")


def key_name(key: str) -> str:
    """The Playwright name of a key as agents write it (``ctrl``, ``left``, ``a``, ``Enter``)."""
    named = _KEY_ALIASES.get(key.lower())
    if named:
        return named
    if len(key) == 1 or _NAMED_KEY.match(key) or key in _KEY_ALIASES.values():
        return key
    raise GestureError("UNKNOWN_KEY", f"unknown key {key!r}; use a character or a name like Enter, ctrl, left, F5")


class Gestures:
    """Executes primitive actions on one page; index targets resolve against ``elements``."""

    def __init__(
        self,
        page: Page,
        pass_time: Callable[[float], Awaitable[None]] | None = None,
        links: Callable[[], Awaitable[JsonValue]] | None = None,
        dragging: Callable[[], Awaitable[JsonValue]] | None = None,
    ) -> None:
        """``pass_time(ms)``: let page time pass between a drag's moves (on an episode's virtual clock,
        where it would otherwise stand still through the whole gesture); None: it passes by itself.
        ``links()``: the workspace's block links (the bridge's ``primitiveLinks``), read around a drag
        so its record says whether it snapped; None: drags are recorded without.
        ``dragging()``: whether the press started an HTML5 drag still under way (the bridge's
        ``primitiveDragging``), read once in a drag on the virtual clock: with none, the drag's later moves
        skip Playwright's drag interception (``_pressed_moves``); None: every move goes through it."""
        self.page = page
        self.pass_time = pass_time
        self.links = links
        self.dragging = dragging
        self.elements: Sequence[Located] | None = None
        """The element list of the latest observation (None until the first one)."""

    async def execute(self, api: str, args: dict[str, JsonValue]) -> ActionEnvelope:
        started = time.perf_counter()

        def elapsed() -> float:
            return (time.perf_counter() - started) * 1000

        handler = self._handlers().get(api)
        if handler is None:
            apis = ", ".join([*PRIMITIVE_APIS, "done", "failed"])
            return ActionEnvelope.failure("UNKNOWN_API", f"unknown api {api[:80]!r}; apis: {apis}", elapsed())
        try:
            data = await handler(args)
        except ValidationError as exc:
            problems = "; ".join(f"{'.'.join(map(str, e['loc'])) or 'args'}: {e['msg']}" for e in exc.errors())
            return ActionEnvelope.failure("INVALID_ARG", f"{api}: {problems}", elapsed())
        except GestureError as exc:
            return ActionEnvelope.failure(exc.code, str(exc), elapsed())
        return ActionEnvelope(success=True, data=data, duration_ms=elapsed())

    def _handlers(self) -> dict[str, Callable[[dict[str, JsonValue]], Awaitable[JsonValue]]]:
        return {
            "click": lambda args: self._click(PointArgs.model_validate(args), clicks=1),
            "double_click": lambda args: self._click(PointArgs.model_validate(args), clicks=2),
            "drag_and_drop": lambda args: self._drag(DragArgs.model_validate(args)),
            "scroll": lambda args: self._scroll(ScrollArgs.model_validate(args)),
            "type": lambda args: self._type(TypeArgs.model_validate(args)),
            "key": lambda args: self._key(KeyArgs.model_validate(args)),
            "hotkey": lambda args: self._hotkey(HotkeyArgs.model_validate(args)),
        }

    def _point(self, x: float | None, y: float | None, index: int | None) -> tuple[float, float]:
        if index is not None:
            if self.elements is None:
                raise GestureError("STALE_INDEX", "no element list has been observed yet; use x and y")
            if index >= len(self.elements):
                raise GestureError(
                    "STALE_INDEX", f"index {index} is not in the latest element list (0-{len(self.elements) - 1})"
                )
            x, y = self.elements[index].center
        if x is None or y is None:  # the argument models rule this out
            raise GestureError("INVALID_ARG", "no target point")
        size = self.page.viewport_size or {"width": 0, "height": 0}
        if not (0 <= x < size["width"] and 0 <= y < size["height"]):
            raise GestureError(
                "OUT_OF_VIEWPORT", f"({x:g}, {y:g}) is outside the {size['width']}x{size['height']} viewport"
            )
        return x, y

    async def _click(self, args: PointArgs, clicks: int) -> JsonValue:
        x, y = self._point(args.x, args.y, args.index)
        await self.page.mouse.click(x, y, button=args.button, click_count=clicks)
        return {"x": x, "y": y}

    async def _drag(self, args: DragArgs) -> JsonValue:
        start = self._point(args.start_x, args.start_y, args.start_index)
        end = self._point(args.end_x, args.end_y, args.end_index)
        before = await self._parents()
        mouse = self.page.mouse
        await mouse.move(*start)
        await mouse.down()
        # Scratch starts a drag and shows the snap preview only on real intermediate moves.
        steps = max(10, int(args.duration * 30))
        pass_time = self.pass_time
        if pass_time is None:
            await mouse.move(*end, steps=steps)
        else:  # on an episode's virtual clock the gesture's duration goes by between its moves
            step_ms = args.duration * 1000 / steps
            await pressed_moves(self.page, start, end, steps, lambda: pass_time(step_ms), self.dragging)
        await mouse.up()
        data: dict[str, JsonValue] = {"start": list(start), "end": list(end)}
        if before is not None and (after := await self._parents()) is not None:
            # Snapped: some block (the dropped one, or one a drop went between) hangs from a new parent.
            parent_before = {block: parent for block, (parent, _) in before.items()}
            attached = sorted(
                opcode for block, (parent, opcode) in after.items() if parent and parent != parent_before.get(block)
            )
            data.update(snapped=bool(attached), attached=list(attached))
        return data

    async def _parents(self) -> dict[str, tuple[str | None, str]] | None:
        """Each workspace block's (parent, opcode), or None when drags are recorded without links."""
        if self.links is None:
            return None
        reply = await self.links()
        rows = reply.get("links") if isinstance(reply, dict) else None
        if not isinstance(rows, list):
            return None
        parents: dict[str, tuple[str | None, str]] = {}
        for row in rows:
            if isinstance(row, list) and len(row) == 3:
                parents[str(row[0])] = (row[1] if isinstance(row[1], str) else None, str(row[2]))
        return parents

    async def _scroll(self, args: ScrollArgs) -> JsonValue:
        if args.x is not None or args.index is not None:
            await self.page.mouse.move(*self._point(args.x, args.y, args.index))
        dx = {"left": -args.amount, "right": args.amount}.get(args.direction, 0)
        dy = {"up": -args.amount, "down": args.amount}.get(args.direction, 0)
        await self.page.mouse.wheel(dx, dy)
        return {"dx": dx, "dy": dy}

    async def _type(self, args: TypeArgs) -> JsonValue:
        await self.page.keyboard.type(args.text)
        return {"typed": len(args.text)}

    async def _key(self, args: KeyArgs) -> JsonValue:
        name = key_name(args.key)
        await self._press(name)
        return {"key": name}

    async def _hotkey(self, args: HotkeyArgs) -> JsonValue:
        names = [key_name(key) for key in args.keys]
        keyboard = self.page.keyboard
        for name in names[:-1]:
            await keyboard.down(name)
        try:
            await self._press(names[-1])
        finally:
            for name in reversed(names[:-1]):
                await keyboard.up(name)
        return {"keys": names}

    async def _press(self, name: str) -> None:
        try:
            await self.page.keyboard.press(name)
        except PlaywrightError as exc:
            if "Unknown key" in exc.message:
                raise GestureError("UNKNOWN_KEY", f"unknown key {name!r}") from exc
            raise
