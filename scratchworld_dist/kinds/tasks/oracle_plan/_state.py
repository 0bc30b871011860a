"""A loaded project as the planner reads it from the page (``oracleProjectState``), as typed data."""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field, JsonValue

from workers.editor import Editor


class _PageModel(BaseModel):
    model_config = ConfigDict(frozen=True, extra="ignore", populate_by_name=True)


class FieldState(_PageModel):
    value: str
    id: str | None = None


class InputState(_PageModel):
    block: str | None = None
    """What the input holds: a block, its shadow, or nothing."""

    shadow: str | None = None


class BlockState(_PageModel):
    id: str
    opcode: str
    shadow: bool = False
    top_level: bool = Field(False, alias="topLevel")
    parent: str | None = None
    next: str | None = None
    fields: dict[str, FieldState] = Field(default_factory=dict)
    inputs: dict[str, InputState] = Field(default_factory=dict)
    mutation: JsonValue = None
    x: float | None = None
    y: float | None = None
    """Where a script's first block sits (the VM reassigns ids on a load, so order comes from here)."""

    def held(self, name: str) -> str | None:
        """The non-shadow block in input ``name``, if any."""
        slot = self.inputs.get(name)
        if slot is None or slot.block is None or slot.block == slot.shadow:
            return None
        return slot.block


class VariableState(_PageModel):
    id: str
    name: str
    type: str = ""
    """``""`` a variable, ``list``, or ``broadcast_msg``."""


class AssetState(_PageModel):
    name: str
    asset_id: str | None = Field(None, alias="assetId")


class TargetState(_PageModel):
    name: str
    is_stage: bool = Field(alias="isStage")
    variables: list[VariableState] = Field(default_factory=list)
    costumes: list[AssetState] = Field(default_factory=list)
    sounds: list[AssetState] = Field(default_factory=list)
    x: float = 0
    y: float = 0
    direction: float = 90
    size: float = 100
    visible: bool = True
    current_costume: int = Field(0, alias="currentCostume")
    rotation_style: str | None = Field(None, alias="rotationStyle")
    blocks: dict[str, BlockState] = Field(default_factory=dict)


class ProjectState(_PageModel):
    editing_target: str | None = Field(None, alias="editingTarget")
    targets: list[TargetState]

    def target(self, name: str, is_stage: bool) -> TargetState | None:
        """The stage, or the sprite named ``name`` (else the one sprite whose name differs only in case,
        as ``select_sprite`` finds it)."""
        if is_stage:
            return next((t for t in self.targets if t.is_stage), None)
        sprites = [t for t in self.targets if not t.is_stage]
        exact = next((t for t in sprites if t.name == name), None)
        if exact is not None:
            return exact
        folded = [t for t in sprites if t.name.lower() == name.lower()]
        return folded[0] if len(folded) == 1 else None


class BlockIndexes(_PageModel):
    editing_target: str = Field(alias="editingTarget")
    ids: list[str]

    def index(self, block_id: str) -> int:
        """The ``#n`` composite calls name this block by."""
        return self.ids.index(block_id) + 1


async def read_state(editor: Editor) -> ProjectState:
    return ProjectState.model_validate(await editor.call("oracleProjectState"))


async def read_indexes(editor: Editor) -> BlockIndexes:
    return BlockIndexes.model_validate(await editor.call("oracleBlockIndexes"))
