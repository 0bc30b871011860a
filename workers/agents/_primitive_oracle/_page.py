"""The oracle's reads of the editor page: geometry and bounded waits, each reply validated.

Between gestures the oracle only reads; every read goes through ``Page``, which turns a reply of
an unexpected shape into an ``OracleDivergenceError`` with a one-line reason.
"""

from __future__ import annotations

from typing import Any, TypeVar

from pydantic import BaseModel, JsonValue, ValidationError

from workers.agents._primitive_oracle._divergence import OracleDivergenceError, OracleWaitError, describe_difference
from workers.agents._primitive_oracle._geometry import (
    BlockGeometry,
    ColourPicker,
    DragPlan,
    FieldGeometry,
    FlyoutBlock,
    FlyoutBlockReply,
    FlyoutButton,
    FlyoutButtonReply,
    FreeSpot,
    Layout,
    Menu,
    ModalReply,
    OpenModal,
    PaletteMiss,
    Point,
    Rect,
    StagePixel,
    TextEditor,
)
from workers.agents._primitive_oracle._state import (
    BlockFields,
    BlockIds,
    BlockPaths,
    ProjectSnapshot,
    Snapshot,
    TopBlocks,
    WaitResult,
)
from workers.editor import Editor

WAIT_MS = 5000
SNAPSHOT_WAIT_MS = 4000
MAX_PROBLEMS = 3
"""Validation problems named in one error message."""

M = TypeVar("M", bound=BaseModel)


def parse(model: type[M], reply: JsonValue, call: str) -> M:
    """``reply`` as ``model``, or an ``OracleDivergenceError`` naming what does not fit."""
    try:
        return model.model_validate(reply)
    except ValidationError as exc:
        errors = exc.errors()
        problems = "; ".join(
            f"{'.'.join(str(part) for part in error['loc']) or 'reply'}: {error['msg']}"
            for error in errors[:MAX_PROBLEMS]
        )
        more = f" (+{len(errors) - MAX_PROBLEMS} more)" if len(errors) > MAX_PROBLEMS else ""
        raise OracleDivergenceError(f"{call} answered a reply the oracle cannot use: {problems}{more}") from None


class Page:
    """Read-only access to one editor page, as typed geometry."""

    def __init__(self, editor: Editor) -> None:
        self.editor = editor

    async def _call(self, name: str, args: dict[str, Any] | None = None) -> JsonValue:
        # Looked up on every call: tests record the calls by replacing ``editor.call``.
        return await self.editor.call(name, args)

    async def layout(self) -> Layout:
        return parse(Layout, await self._call("geometryLayout"), "geometryLayout")

    async def block(self, block_id: str) -> BlockGeometry:
        return parse(BlockGeometry, await self._call("geometryBlock", {"id": block_id}), "geometryBlock")

    async def field(self, block_id: str, name: str) -> tuple[FieldGeometry, Rect]:
        """The field and where it is drawn (it must be)."""
        reply = await self._call("geometryField", {"id": block_id, "name": name})
        field = parse(FieldGeometry, reply, "geometryField")
        if field.rect is None:
            raise OracleDivergenceError(f"field {name} of block {block_id} is not drawn")
        return field, field.rect

    async def block_fields(self, block_id: str) -> BlockFields:
        return parse(BlockFields, await self._call("geometryBlockFields", {"id": block_id}), "geometryBlockFields")

    async def flyout_block(self, opcode: str, variable: str | None) -> FlyoutBlock | PaletteMiss:
        reply = await self._call("geometryFlyoutBlock", {"opcode": opcode, "variableName": variable})
        return parse(FlyoutBlockReply, reply, "geometryFlyoutBlock").root

    async def flyout_button(self, text: str) -> FlyoutButton | PaletteMiss:
        reply = await self._call("geometryFlyoutButton", {"text": text})
        return parse(FlyoutButtonReply, reply, "geometryFlyoutButton").root

    async def menu(self) -> Menu:
        return parse(Menu, await self._call("geometryMenu"), "geometryMenu")

    async def text_editor(self) -> TextEditor:
        return parse(TextEditor, await self._call("geometryTextEditor"), "geometryTextEditor")

    async def colour_picker(self) -> ColourPicker:
        return parse(ColourPicker, await self._call("geometryColourPicker"), "geometryColourPicker")

    async def stage_pixel(self, colour: str) -> StagePixel:
        return parse(StagePixel, await self._call("geometryStagePixel", {"colour": colour}), "geometryStagePixel")

    async def modal(self) -> OpenModal:
        """The open prompt; one that closed on its own is a divergence."""
        modal = parse(ModalReply, await self._call("geometryModal"), "geometryModal").root
        if not isinstance(modal, OpenModal):
            raise OracleDivergenceError("the prompt closed before it was filled in")
        return modal

    async def free_spot(
        self, width: float, height: float, near: Point | None, ignore: list[str] | None = None
    ) -> Point | None:
        """Top-left corner of an empty ``width`` x ``height`` box nearest to ``near``; None when none is visible."""
        args: dict[str, Any] = {"width": width, "height": height, "ignore": ignore or []}
        if near is not None:
            args["near"] = {"x": near.x, "y": near.y}
        return parse(FreeSpot, await self._call("geometryFreeSpot", args), "geometryFreeSpot").spot

    async def plan_drag(self, args: dict[str, Any]) -> DragPlan:
        return parse(DragPlan, await self._call("geometryPlanDrag", args), "geometryPlanDrag")

    async def top_blocks(self) -> TopBlocks:
        return parse(TopBlocks, await self._call("geometryTopBlocks"), "geometryTopBlocks")

    async def paths(self) -> dict[str, dict[str, str]]:
        return parse(BlockPaths, await self._call("geometryBlockPaths"), "geometryBlockPaths").paths

    async def snapshot(self) -> Snapshot:
        return parse(Snapshot, await self._call("geometrySnapshot"), "geometrySnapshot")

    async def block_ids(self) -> list[str | None]:
        """The editing target's block ids by composite index (the dry run's one read of composite mode)."""
        return parse(BlockIds, await self._call("compositeBlockIds"), "compositeBlockIds").ids

    async def wait_result(
        self, until: str, args: dict[str, Any] | None = None, timeout_ms: int = WAIT_MS
    ) -> WaitResult:
        reply = await self._call("geometryWait", {"until": until, "args": args or {}, "timeoutMs": timeout_ms})
        return parse(WaitResult, reply, "geometryWait")

    async def wait(
        self, until: str, args: dict[str, Any] | None = None, *, what: str, timeout_ms: int = WAIT_MS
    ) -> None:
        """Wait (bounded) for a condition after a gesture; giving up may be the machine's slowness: retried."""
        result = await self.wait_result(until, args, timeout_ms)
        if not result.ok:
            raise OracleWaitError(
                f"gave up waiting for {what} after {timeout_ms / 1000:g} s ({until}: {result.value!r})"
            )

    async def expect_state(self, expected: str, when: str) -> None:
        """The project must mean what the dry run's did (``expected``: a snapshot's text), within a bounded wait."""
        result = await self.wait_result("snapshot", {"expected": expected}, SNAPSHOT_WAIT_MS)
        if not result.ok:
            difference = describe_difference(ProjectSnapshot.model_validate_json(expected), result.value)
            raise OracleDivergenceError(f"{when}, the GUI project differs from the composite dry run: {difference}")
