"""A Scratch 3 program as typed objects: targets, blocks and their links, read from project.json and written back.

Mutants and refactorings are made through this model, never by editing JSON: the edits (``_edits.py``) work
on blocks and their ``parent``/``next``/input links, and ``to_project`` writes the dict again. Everything the
model does not interpret (costumes, a block's mutation or comment, monitors, meta) is kept as it was, so
reading then writing an unchanged program gives an equal dict, and editing one block changes only what that
edit touches. Block ids are kept; new blocks get ids derived from what creates them (``fresh_id``).
"""

from __future__ import annotations

import hashlib
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any, Literal

INPUT_SHADOW = 1
"""An input that holds only its shadow (a literal or a menu)."""
INPUT_BLOCK = 2
"""An input that holds a block and no shadow (boolean slots, substacks)."""
INPUT_OBSCURED = 3
"""An input that holds a block over a shadow (a reporter dropped on a literal)."""

BROADCAST_CODE, VARIABLE_CODE, LIST_CODE = 11, 12, 13
"""Compact inputs ``[code, name, id]`` for a broadcast menu, a variable reporter and a list reporter."""

VarKind = Literal["variable", "list"]
REFERENCE_FIELD: dict[VarKind, str] = {"variable": "VARIABLE", "list": "LIST"}
REFERENCE_CODE: dict[VarKind, int] = {"variable": VARIABLE_CODE, "list": LIST_CODE}

_BLOCK_KEYS = ("opcode", "next", "parent", "inputs", "fields", "shadow", "topLevel", "x", "y")


class ProgramFormatError(ValueError):
    """project.json that the model cannot read: says which target and block, and what is wrong."""


@dataclass
class Primitive:
    """An inline value ``[code, value, *rest]``: a literal (4-10), or a broadcast, variable or list (11-13:
    ``rest`` is ``[id]``, plus ``[x, y]`` when the array lies loose on the workspace)."""

    code: int
    value: Any
    rest: list[Any] = field(default_factory=list)

    @property
    def ref_id(self) -> str | None:
        """The id of the broadcast, variable or list it names (None for a literal)."""
        return self.rest[0] if self.code >= BROADCAST_CODE and self.rest and isinstance(self.rest[0], str) else None

    def copy(self) -> Primitive:
        return Primitive(self.code, self.value, list(self.rest))

    def to_json(self) -> list[Any]:
        return [self.code, self.value, *self.rest]


Slot = str | Primitive | None
"""What an input slot holds: a block id, an inline value, or nothing."""


@dataclass
class Input:
    """``[kind, value]`` or ``[kind, value, shadow]``: for kind 1 the value is the shadow itself; for 3 the
    shadow lies under the block and is not seen."""

    kind: int
    value: Slot
    shadow: Slot = None
    has_shadow: bool = False

    @property
    def block_id(self) -> str | None:
        """The block plugged in (not a shadow)."""
        return self.value if self.kind != INPUT_SHADOW and isinstance(self.value, str) else None

    @property
    def literal(self) -> Primitive | None:
        """The visible inline value, when the slot shows one."""
        return self.value if self.kind == INPUT_SHADOW and isinstance(self.value, Primitive) else None

    def copy(self) -> Input:
        return Input(self.kind, _slot_copy(self.value), _slot_copy(self.shadow), self.has_shadow)

    def block_refs(self) -> list[str]:
        """Every block id in the input: the block and its shadow."""
        return [slot for slot in (self.value, self.shadow) if isinstance(slot, str)]

    def to_json(self) -> list[Any]:
        items = [self.kind, _slot_json(self.value)]
        return [*items, _slot_json(self.shadow)] if self.has_shadow else items


@dataclass
class Field:
    """``[value]`` or ``[value, id]`` (the id of a variable, list or broadcast; None for other fields)."""

    value: Any
    id: str | None = None
    has_id: bool = True

    def to_json(self) -> list[Any]:
        return [self.value, self.id] if self.has_id else [self.value]


@dataclass
class Block:
    id: str
    opcode: str
    next: str | None = None
    parent: str | None = None
    inputs: dict[str, Input] = field(default_factory=dict)
    fields: dict[str, Field] = field(default_factory=dict)
    shadow: bool = False
    top_level: bool = False
    position: tuple[Any, Any] | None = None
    """(x, y) on the workspace: top-level blocks have one."""
    extra: dict[str, Any] = field(default_factory=dict)
    """Keys the model keeps without reading (mutation, comment...): never edited, so copies share it."""

    def copy(self) -> Block:
        return Block(
            self.id,
            self.opcode,
            self.next,
            self.parent,
            {name: entry.copy() for name, entry in self.inputs.items()},
            {name: Field(f.value, f.id, f.has_id) for name, f in self.fields.items()},
            self.shadow,
            self.top_level,
            self.position,
            self.extra,
        )

    def to_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {
            "opcode": self.opcode,
            "next": self.next,
            "parent": self.parent,
            "inputs": {name: entry.to_json() for name, entry in self.inputs.items()},
            "fields": {name: entry.to_json() for name, entry in self.fields.items()},
            "shadow": self.shadow,
            "topLevel": self.top_level,
        }
        if self.position is not None:
            out["x"], out["y"] = self.position
        return {**out, **json_copy(self.extra)} if self.extra else out


@dataclass
class Target:
    """The stage or a sprite: its blocks (in project order, which is the order its scripts start in) and the
    variables, lists and broadcasts it declares."""

    name: str
    is_stage: bool
    blocks: dict[str, Block | Primitive]
    variables: dict[str, list[Any]]
    lists: dict[str, list[Any]]
    broadcasts: dict[str, Any]
    comments: dict[str, Any]
    raw: dict[str, Any]
    """The target's JSON as read (its blocks left out): never edited, so copies share it."""

    def copy(self) -> Target:
        """A copy to edit (what edits change is copied; the rest is shared)."""
        blocks = {k: b.copy() for k, b in self.blocks.items()}
        pools = [json_copy(pool) for pool in (self.variables, self.lists, self.broadcasts, self.comments)]
        return Target(self.name, self.is_stage, blocks, *pools, raw=self.raw)

    def block(self, block_id: str) -> Block:
        found = self.blocks.get(block_id)
        if not isinstance(found, Block):
            raise ProgramFormatError(f"target {self.name!r}: no block {block_id!r}")
        return found

    def all_blocks(self) -> Iterator[Block]:
        return (b for b in self.blocks.values() if isinstance(b, Block))

    def scripts(self) -> list[str]:
        """The top blocks of its scripts, in project order (loose variable reporters are no scripts)."""
        return [b.id for b in self.all_blocks() if b.top_level and not b.shadow]

    def stack(self, first: str | None) -> list[str]:
        """The ids of a stack from ``first`` down, following ``next``."""
        ids: list[str] = []
        while first is not None and first not in ids:
            ids.append(first)
            first = self.block(first).next
        return ids

    def top_of(self, block_id: str) -> str:
        """The top block of the script ``block_id`` is in."""
        seen = {block_id}
        while (parent := self.block(block_id).parent) is not None and parent not in seen:
            seen.add(parent)
            block_id = parent
        return block_id

    def subtree(self, block_id: str) -> list[str]:
        """A block and everything in its inputs (substacks, reporters, shadows), not the blocks after it."""
        found: dict[str, None] = {}
        todo = [block_id]
        while todo:
            current = todo.pop()
            block = self.blocks.get(current)
            if current in found or not isinstance(block, Block):
                continue
            found[current] = None
            if current != block_id and block.next is not None:  # the rest of a substack
                todo.append(block.next)
            for entry in reversed(block.inputs.values()):
                todo += entry.block_refs()
        return list(found)

    def script_blocks(self, top: str) -> list[str]:
        """Every block of the script that starts at ``top``."""
        return [block_id for first in self.stack(top) for block_id in self.subtree(first)]

    def to_json(self) -> dict[str, Any]:
        out = json_copy(self.raw)
        out["blocks"] = {k: b.to_json() for k, b in self.blocks.items()}
        for key, value in (("variables", self.variables), ("lists", self.lists), ("broadcasts", self.broadcasts)):
            if key in self.raw or value:
                out[key] = json_copy(value)
        if "comments" in self.raw or self.comments:
            out["comments"] = json_copy(self.comments)
        return out


@dataclass
class Program:
    """A project's targets (stage first, as Scratch writes them) and the rest of its project.json."""

    targets: list[Target]
    raw: dict[str, Any]

    @classmethod
    def parse(cls, project: Mapping[str, Any]) -> Program:
        """The program of a project dict (copied: editing the program never touches ``project``)."""
        targets = project.get("targets")
        if not isinstance(targets, list):
            raise ProgramFormatError("project.json has no list of targets")
        rest = {k: None if k == "targets" else json_copy(v) for k, v in project.items()}
        return cls([_target(t, i) for i, t in enumerate(targets)], rest)

    def copy(self) -> Program:
        """A copy to edit, much cheaper than reading the project again."""
        return Program([t.copy() for t in self.targets], json_copy(self.raw))

    def to_project(self) -> dict[str, Any]:
        """The project dict: the same keys as read, targets written from the model."""
        out = json_copy(self.raw)
        out["targets"] = [t.to_json() for t in self.targets]
        return out

    @property
    def stage(self) -> Target:
        return next((t for t in self.targets if t.is_stage), self.targets[0])

    def target(self, name: str) -> Target:
        found = next((t for t in self.targets if t.name == name), None)
        if found is None:
            raise ProgramFormatError(f"the project has no target named {name!r}")
        return found

    def in_scope(self, target: Target, kind: VarKind) -> dict[str, str]:
        """id -> name of the variables (or lists) a script of ``target`` can use: its own, then the stage's."""
        owners = [target] if target.is_stage else [target, self.stage]
        return {
            var_id: str(entry[0])
            for owner in owners
            for var_id, entry in (owner.variables if kind == "variable" else owner.lists).items()
        }

    def fresh_id(self, seed: str) -> str:
        """A block, variable or broadcast id used nowhere in the project, derived from ``seed`` (deterministic)."""
        taken = {k for t in self.targets for pool in (t.blocks, t.variables, t.lists, t.broadcasts) for k in pool}
        base = "audit-" + hashlib.sha256(seed.encode()).hexdigest()[:10]
        candidate, n = base, 1
        while candidate in taken:
            n += 1
            candidate = f"{base}-{n}"
        return candidate


def json_copy(value: Any) -> Any:
    """A copy of JSON data (dicts, lists, scalars), many times faster than ``copy.deepcopy``."""
    if isinstance(value, dict):
        return {k: json_copy(v) for k, v in value.items()}
    if isinstance(value, list):
        return [json_copy(v) for v in value]
    return value


def _slot_copy(slot: Slot) -> Slot:
    return slot.copy() if isinstance(slot, Primitive) else slot


def _slot_json(slot: Slot) -> Any:
    return slot.to_json() if isinstance(slot, Primitive) else slot


def _target(raw: Any, index: int) -> Target:
    if not isinstance(raw, dict):
        raise ProgramFormatError(f"target {index} is not an object")
    name = str(raw.get("name", f"#{index}"))
    blocks_raw = raw.get("blocks", {})
    if not isinstance(blocks_raw, dict):
        raise ProgramFormatError(f"target {name!r}: blocks is not an object")
    pools = {}
    for key in ("variables", "lists", "broadcasts", "comments"):
        pool = raw.get(key, {})
        if not isinstance(pool, dict):
            raise ProgramFormatError(f"target {name!r}: {key} is not an object")
        pools[key] = json_copy(pool)
    kept = {k: None if k == "blocks" else json_copy(v) for k, v in raw.items()}
    blocks = {str(block_id): _block(name, str(block_id), b) for block_id, b in blocks_raw.items()}
    return Target(name, bool(raw.get("isStage")), blocks, raw=kept, **pools)


def _block(target: str, block_id: str, raw: Any) -> Block | Primitive:
    where = f"target {target!r}, block {block_id!r}"
    if isinstance(raw, list):
        return _primitive(where, raw)
    if not isinstance(raw, dict) or not isinstance(raw.get("opcode"), str):
        raise ProgramFormatError(f"{where}: not a block (no opcode)")
    inputs, fields = raw.get("inputs", {}), raw.get("fields", {})
    if not isinstance(inputs, dict) or not isinstance(fields, dict):
        raise ProgramFormatError(f"{where}: inputs and fields must be objects")
    for key in ("next", "parent"):
        if raw.get(key) is not None and not isinstance(raw.get(key), str):
            raise ProgramFormatError(f"{where}: {key} must be a block id or null")
    return Block(
        id=block_id,
        opcode=raw["opcode"],
        next=raw.get("next"),
        parent=raw.get("parent"),
        inputs={str(n): _input(f"{where}, input {n!r}", v) for n, v in inputs.items()},
        fields={str(n): _field(f"{where}, field {n!r}", v) for n, v in fields.items()},
        shadow=bool(raw.get("shadow", False)),
        top_level=bool(raw.get("topLevel", False)),
        position=(raw["x"], raw["y"]) if "x" in raw and "y" in raw else None,
        extra={k: json_copy(v) for k, v in raw.items() if k not in _BLOCK_KEYS},
    )


def _primitive(where: str, raw: list[Any]) -> Primitive:
    if len(raw) < 2 or not isinstance(raw[0], int):
        raise ProgramFormatError(f"{where}: an inline value must be [code, value, ...], got {raw!r}"[:300])
    return Primitive(raw[0], raw[1], list(raw[2:]))


def _slot(where: str, raw: Any) -> Slot:
    if raw is None or isinstance(raw, str):
        return raw
    if isinstance(raw, list):
        return _primitive(where, raw)
    raise ProgramFormatError(f"{where}: a slot holds a block id, an inline value or null, got {raw!r}"[:300])


def _input(where: str, raw: Any) -> Input:
    if not isinstance(raw, list) or len(raw) not in (2, 3) or raw[0] not in (1, 2, 3):
        raise ProgramFormatError(f"{where}: an input must be [1|2|3, value(, shadow)], got {raw!r}"[:300])
    shadow = _slot(where, raw[2]) if len(raw) == 3 else None
    return Input(raw[0], _slot(where, raw[1]), shadow, has_shadow=len(raw) == 3)


def _field(where: str, raw: Any) -> Field:
    if not isinstance(raw, list) or len(raw) not in (1, 2):
        raise ProgramFormatError(f"{where}: a field must be [value] or [value, id], got {raw!r}"[:300])
    return Field(raw[0], raw[1] if len(raw) == 2 else None, has_id=len(raw) == 2)
