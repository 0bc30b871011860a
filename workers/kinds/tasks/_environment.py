"""The boundary between an agent and the editor: one observe/execute pair per mode.

The episode runner only ever talks to an ``Environment``; everything mode-specific (the
composite API in the page, or screenshots, element lists and real mouse gestures) lives behind
it, so an agent written for one mode cannot reach the other's means by accident.
"""

from __future__ import annotations

from collections.abc import Awaitable, Callable
from typing import Protocol

from playwright.async_api import Error as PlaywrightError

from workers import composite
from workers.contract import (
    ActionEnvelope,
    CompositeAction,
    CompositeObservation,
    EditorCrashedError,
    Observation,
    PrimitiveAction,
    PrimitiveObservation,
)
from workers.editor import Editor
from workers.primitive import Gestures, PrimitiveObserver


class Environment(Protocol):
    editor: Editor
    """The page the agent works in."""

    async def observe(self) -> Observation: ...

    async def execute(self, action: CompositeAction | PrimitiveAction) -> ActionEnvelope: ...

    async def block_catalog(self) -> str | None:
        """The blocks an agent may create by name (composite mode), for its instructions."""
        ...


class CompositeEnvironment:
    """The semantic block-editing API; primitive actions are refused."""

    def __init__(self, editor: Editor) -> None:
        self.editor = editor

    async def observe(self) -> CompositeObservation:
        return await composite.observe(self.editor)

    async def execute(self, action: CompositeAction | PrimitiveAction) -> ActionEnvelope:
        if isinstance(action, PrimitiveAction):
            return _wrong_mode(action.api, "composite")
        return await composite.execute(self.editor, action.api, action.args)

    async def block_catalog(self) -> str:
        return await composite.block_catalog(self.editor)


class PrimitiveEnvironment:
    """Screenshots plus element lists, and real mouse and keyboard; composite calls are refused."""

    def __init__(
        self, editor: Editor, observer: PrimitiveObserver, pass_time: Callable[[float], Awaitable[None]] | None = None
    ) -> None:
        """``pass_time``: see ``Gestures`` (set on an episode's virtual clock)."""
        self.editor = editor
        self.observer = observer
        self.gestures = Gestures(
            editor.page,
            pass_time,
            links=lambda: editor.call("primitiveLinks"),
            dragging=lambda: editor.call("primitiveDragging"),
        )

    async def observe(self) -> PrimitiveObservation:
        observation = await self.observer.observe(self.editor)
        self.gestures.elements = observation.elements
        return observation

    async def execute(self, action: CompositeAction | PrimitiveAction) -> ActionEnvelope:
        if isinstance(action, CompositeAction):
            return _wrong_mode(action.api, "primitive")
        try:
            return await self.gestures.execute(action.api, action.args)
        except PlaywrightError as exc:
            raise EditorCrashedError(f"the page did not take the {action.api} gesture: {exc.message}") from exc

    async def block_catalog(self) -> None:
        return None  # blocks are found in the palette


def _wrong_mode(api: str, mode: str) -> ActionEnvelope:
    return ActionEnvelope.failure("UNKNOWN_API", f"{api!r} is not an action of {mode} mode")
