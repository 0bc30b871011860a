"""Composite mode from Python: the observation text and the envelope every API call returns."""

from __future__ import annotations

from pydantic import BaseModel, JsonValue

from workers.contract import ActionEnvelope, CompositeObservation
from workers.editor import Editor

MAX_CHOICES = 12
"""Dropdown choices listed per field in the block catalog (key menus have 40+)."""


class CatalogInput(BaseModel):
    name: str
    kind: str


class CatalogField(BaseModel):
    name: str
    choices: list[str] | None = None


class CatalogBlock(BaseModel):
    """One block of the editor's catalog, as the page describes it."""

    opcode: str
    shape: str
    inputs: list[CatalogInput]
    fields: list[CatalogField]


def render_catalog(blocks: list[CatalogBlock]) -> str:
    """One line per block: ``opcode (shape): INPUT <value>, SUBSTACK {statement}, FIELD [choices]``."""
    lines = []
    for block in blocks:
        parts = [f"{i.name} <{i.kind}>" if i.kind != "statement" else f"{i.name} {{statement}}" for i in block.inputs]
        for field in block.fields:
            if field.name in ("VARIABLE", "LIST", "BROADCAST_OPTION") or field.choices is None:
                parts.append(f"{field.name} [name]")
            else:
                shown = [str(c) for c in field.choices[:MAX_CHOICES]]
                more = ", ..." if len(field.choices) > MAX_CHOICES else ""
                parts.append(f"{field.name} [{', '.join(shown)}{more}]")
        lines.append(f"{block.opcode} ({block.shape})" + (": " + ", ".join(parts) if parts else ""))
    return "\n".join(lines)


async def observe(editor: Editor) -> CompositeObservation:
    return CompositeObservation.model_validate(await editor.call("compositeObserve"))


async def execute(editor: Editor, api: str, args: dict[str, JsonValue]) -> ActionEnvelope:
    """Run one action; agent mistakes come back as an error envelope, never as an exception."""
    return ActionEnvelope.model_validate(await editor.call("compositeExecute", {"api": api, "args": args}))


async def block_catalog(editor: Editor) -> str:
    """The blocks ``add_block`` can create for the editing target, one line each (see ``render_catalog``)."""
    raw = await editor.call("compositeCatalog")
    return render_catalog([CatalogBlock.model_validate(block) for block in raw["blocks"]])


async def sync_workspace(editor: Editor) -> None:
    """Redraw the visible workspace from the VM (composite edits skip it to stay fast)."""
    await editor.call("compositeSyncWorkspace")
