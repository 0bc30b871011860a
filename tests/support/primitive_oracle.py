"""Driving the primitive oracle in a real editor as the episode runner does, and comparing what its
gestures build with what the composite API builds from the same trajectory."""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from tests.conftest import primitive_editor
from workers import composite
from workers.agents._primitive_oracle import PrimitiveOracle
from workers.contract import CompositeAction, Done, PrimitiveAction
from workers.editor import Editor, EditorPool
from workers.primitive import Gestures

Tamper = Callable[[int, PrimitiveAction], PrimitiveAction]


@dataclass
class Run:
    """What one oracle run did on the page."""

    gestures: int
    seconds: float
    calls: list[str]
    """Bridge functions called after ``begin`` (the real run)."""
    actions: list[PrimitiveAction]


async def drive(editor: Editor, oracle: PrimitiveOracle, tamper: Tamper | None = None) -> Run:
    """Execute the oracle's gestures with ``Gestures`` until it says done, as the episode runner does."""
    started = time.monotonic()
    calls: list[str] = []
    bridge = editor.call

    async def recording(name: str, args: dict[str, Any] | None = None) -> Any:
        calls.append(name)
        return await bridge(name, args)

    editor.call = recording  # type: ignore[method-assign]
    gestures = Gestures(editor.page)
    count = 0
    actions: list[PrimitiveAction] = []
    try:
        while not isinstance(action := await oracle.act(None), Done):
            assert isinstance(action, PrimitiveAction), action
            if tamper is not None:
                action = tamper(count, action)
            envelope = await gestures.execute(action.api, action.args)
            assert envelope.success, (action, envelope.error)
            actions.append(action)
            count += 1
    finally:
        del editor.call  # back to the method
    return Run(gestures=count, seconds=time.monotonic() - started, calls=calls, actions=actions)


async def sprite_block_ids(editor: Editor, sprite: str) -> dict[str, str]:
    """Block id by opcode among ``sprite``'s blocks (the last of each opcode), ``sprite`` selected."""
    return {opcode: block_id for opcode, (_, block_id) in (await sprite_blocks(editor, sprite)).items()}


async def sprite_blocks(editor: Editor, sprite: str) -> dict[str, tuple[int, str]]:
    """(composite block index, block id) by opcode among ``sprite``'s blocks (the last of each opcode),
    ``sprite`` selected."""
    await composite.execute(editor, "select_sprite", {"name": sprite})
    ids = (await editor.call("compositeBlockIds"))["ids"]  # type: ignore[index,call-overload]
    found: dict[str, tuple[int, str]] = {}
    for index, block_id in enumerate(ids):
        if block_id:
            info = await editor.call("geometryBlock", {"id": block_id})
            found[info["opcode"]] = (index, block_id)  # type: ignore[index,call-overload]
    return found


async def composite_and_oracle(pool: EditorPool, sb3: bytes, trajectory: list[CompositeAction]) -> tuple[str, str, Run]:
    """The workspace ``trajectory`` leaves through the composite API, the one the primitive oracle's gestures
    leave (both as the geometry snapshot's text: scripts, fields and attachments), and the oracle's run."""
    async with primitive_editor(pool, sb3) as editor:
        for action in trajectory:
            envelope = await composite.execute(editor, action.api, action.args)
            assert envelope.success, (action, envelope.error)
        expected = (await editor.call("geometrySnapshot"))["text"]  # type: ignore[index,call-overload]
    async with primitive_editor(pool, sb3) as editor:
        oracle = PrimitiveOracle(sb3, trajectory)
        await oracle.begin(editor)
        run = await drive(editor, oracle)
        performed = (await editor.call("geometrySnapshot"))["text"]  # type: ignore[index,call-overload]
    return expected, performed, run
