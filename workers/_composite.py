"""Composite mode from Python: the observation text and the envelope every API call returns."""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field, JsonValue

from workers._editor import Editor
from workers._envelope import ActionEnvelope


class TargetName(BaseModel):
    model_config = ConfigDict(frozen=True, populate_by_name=True)

    name: str
    is_stage: bool = Field(alias="isStage")


class CompositeObservation(BaseModel):
    """The text an agent reads, and what it describes."""

    model_config = ConfigDict(frozen=True, populate_by_name=True)

    text: str
    editing_target: str = Field(alias="editingTarget")
    block_count: int = Field(alias="blockCount")
    targets: list[TargetName]
    """Every target of the project (stage first), for switching with select_sprite/select_stage."""


async def observe(editor: Editor) -> CompositeObservation:
    return CompositeObservation.model_validate(await editor.call("compositeObserve"))


async def execute(editor: Editor, api: str, args: dict[str, JsonValue]) -> ActionEnvelope:
    """Run one action; agent mistakes come back as an error envelope, never as an exception."""
    return ActionEnvelope.model_validate(await editor.call("compositeExecute", {"api": api, "args": args}))


async def sync_workspace(editor: Editor) -> None:
    """Redraw the visible workspace from the VM (composite edits skip it to stay fast)."""
    await editor.call("compositeSyncWorkspace")
