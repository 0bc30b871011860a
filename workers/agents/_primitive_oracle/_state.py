"""What the project holds, typed: the replies of ``scratch-gui/geometry/`` about the VM, not drawing.

The dry run records these and the real run checks against them: block values as the VM stores
them, scripts without ids or positions, structural block paths, bounded waits for a state, and
(from ``scratch-gui/composite/observation.js``) which block each composite index denotes.
"""

from __future__ import annotations

from typing import Literal

from pydantic import JsonValue, RootModel

from workers.agents._primitive_oracle._geometry import Reply

# ---------- blocks and scripts (geometryBlockFields, geometryTopBlocks, geometryBlockPaths, geometrySnapshot) ---


class BlockFields(Reply):
    """``geometryBlockFields``: a VM block's field values and its shadow inputs' values, as the VM stores them."""

    opcode: str
    fields: dict[str, str]
    inputs: dict[str, str]

    def values(self, kind: Literal["fields", "inputs"]) -> dict[str, str]:
        return self.fields if kind == "fields" else self.inputs


class TopBlock(Reply):
    id: str
    opcode: str


class TopBlocks(Reply):
    """``geometryTopBlocks``: the editing target's scripts, in the VM and on the workspace."""

    vm: list[TopBlock]
    workspace: list[TopBlock]


class BlockPaths(Reply):
    """``geometryBlockPaths``: target name -> block id -> structural path (``Target/script/position/INPUT/...``).

    Paths survive a reload of the project; the ids of compact blocks (variable reporters) do not.
    """

    paths: dict[str, dict[str, str]]


class ScriptBlock(Reply):
    """One block of a snapshot script: ids and positions left out, so equal meaning compares equal."""

    opcode: str
    shadow: bool
    fields: dict[str, str]
    inputs: dict[str, list[ScriptBlock]]


class ScriptChain(RootModel[list[ScriptBlock]]):
    """A script of a snapshot: its top block and the blocks under it."""


class TargetSnapshot(Reply):
    name: str
    is_stage: bool
    variables: list[str]
    """``variable:<name>`` and ``list:<name>``, sorted."""
    scripts: list[str]
    """Each script as the JSON text of its ``ScriptChain``, sorted."""


class ProjectSnapshot(Reply):
    """The semantic state of a project: what two ways of building it must agree on."""

    editing_target: str | None
    targets: list[TargetSnapshot]


class Snapshot(Reply):
    """``geometrySnapshot``: the state, and its JSON text (which ``geometryWait`` compares)."""

    state: ProjectSnapshot
    text: str


# ---------- waiting (geometryWait) ----------


class WaitResult(Reply):
    """``geometryWait``: whether the condition held within the time, and the last value it saw.

    The value's shape is the condition's: the new block's id (``newBlock``), the current snapshot
    (``snapshot``), the value the VM holds (``blockValue``), what keeps the page from settling
    (``quiet``: ``gesture``, ``bump``, ...), or null.
    """

    ok: bool
    value: JsonValue = None
    waited_ms: float


# ---------- composite/observation.js (the dry run's one read of it) ----------


class BlockIds(Reply):
    """``compositeBlockIds``: the ids of the editing target's blocks by composite index (index 0 is unused)."""

    ids: list[str | None]
