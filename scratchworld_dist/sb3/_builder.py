"""A small builder that writes Scratch 3 projects (.sb3) from Python.

It exists so that task projects and test fixtures are source code that can be read and
reviewed, not opaque binaries saved by hand from the editor::

    project = Project()
    ball = project.sprite("Ball", costume=circle_costume("ball", 15, "#e33"))
    ball.script(
        block("event_whenflagclicked"),
        block("control_forever", SUBSTACK=[block("motion_movesteps", STEPS=10),
                                           block("motion_ifonedgebounce")]),
    )
    sb3_bytes = project.to_sb3()

Arguments are checked against ``SHAPES``: an unknown opcode, a misspelt slot, a missing literal,
an unknown variable or list all raise ``ValueError``. Output is deterministic (stable ids, fixed
zip timestamps), so rebuilding an unchanged project gives identical bytes.
"""

from __future__ import annotations

import hashlib
import io
import json
import re
import zipfile
from dataclasses import dataclass, field
from typing import Any, Union

from scratchworld_dist.sb3._catalog import EXTENSIONS, PRIMITIVE_CODES, SHAPES, Slot

Arg = Union[int, float, str, "Block", list["Block"]]


@dataclass
class Block:
    """A block with its slot arguments (inputs and fields by their Scratch names)."""

    opcode: str
    args: dict[str, Arg]

    def __post_init__(self) -> None:
        shape = SHAPES.get(self.opcode)
        if shape is None:
            raise ValueError(f"unknown opcode {self.opcode!r}")
        unknown = set(self.args) - set(shape.inputs) - shape.fields
        if unknown:
            known = sorted(set(shape.inputs) | shape.fields)
            raise ValueError(f"{self.opcode} has no slot {sorted(unknown)}; its slots are {known}")
        missing = [
            name
            for name, slot in shape.inputs.items()
            if slot.kind in ("primitive", "menu", "broadcast") and name not in self.args
        ]
        missing += [name for name in shape.fields if name not in self.args]
        if missing:
            raise ValueError(f"{self.opcode} needs a value for {missing}")


def block(opcode: str, **args: Arg) -> Block:
    """A block; literals, reporter blocks and lists of blocks (stacks) go in by slot name."""
    return Block(opcode, args)


def variable(name: str) -> Block:
    """The reporter of a variable (resolved by name in the sprite, then the stage)."""
    return Block("data_variable", {"VARIABLE": name})


def list_contents(name: str) -> Block:
    """The reporter of a list (resolved by name in the sprite, then the stage)."""
    return Block("data_listcontents", {"LIST": name})


@dataclass(frozen=True)
class Costume:
    """An SVG costume; the asset id is the MD5 of its bytes, as Scratch requires."""

    name: str
    svg: str
    rotation_center: tuple[float, float]

    @property
    def data(self) -> bytes:
        return self.svg.encode("utf-8")

    @property
    def asset_id(self) -> str:
        return hashlib.md5(self.data).hexdigest()


def _svg(width: float, height: float, body: str) -> str:
    return (
        f'<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="{width}" height="{height}" '
        f'viewBox="0 0 {width} {height}">{body}</svg>'
    )


def circle_costume(name: str, radius: float, fill: str) -> Costume:
    size = 2 * radius + 2
    body = f'<circle cx="{size / 2}" cy="{size / 2}" r="{radius}" fill="{fill}" stroke="#000" stroke-width="1"/>'
    return Costume(name, _svg(size, size, body), (size / 2, size / 2))


def rect_costume(name: str, width: float, height: float, fill: str) -> Costume:
    body = f'<rect x="0" y="0" width="{width}" height="{height}" fill="{fill}"/>'
    return Costume(name, _svg(width, height, body), (width / 2, height / 2))


def backdrop_costume(name: str, fill: str = "#ffffff") -> Costume:
    return rect_costume(name, 480, 360, fill)


@dataclass
class _Script:
    blocks: list[Block]
    x: int
    y: int


@dataclass
class Target:
    """The stage or a sprite: costumes, variables, lists and scripts."""

    name: str
    is_stage: bool
    costumes: list[Costume]
    variables: dict[str, Any] = field(default_factory=dict)
    lists: dict[str, list[Any]] = field(default_factory=dict)
    scripts: list[_Script] = field(default_factory=list)
    properties: dict[str, Any] = field(default_factory=dict)

    def variable(self, name: str, value: Any = 0) -> Target:
        """Declare a variable (on the stage: global; on a sprite: for this sprite only)."""
        self.variables[name] = value
        return self

    def list(self, name: str, items: list[Any] | None = None) -> Target:
        self.lists[name] = list(items or [])
        return self

    def script(self, *blocks: Block, x: int | None = None, y: int | None = None) -> Target:
        """Add a stack of blocks (usually starting with a hat) to the workspace."""
        if not blocks:
            raise ValueError("a script needs at least one block")
        position = len(self.scripts)
        self.scripts.append(
            _Script(list(blocks), x if x is not None else 40, y if y is not None else 40 + 220 * position)
        )
        return self


class Project:
    """A Scratch 3 project: a stage with a backdrop and any number of sprites."""

    def __init__(self, backdrop: Costume | None = None) -> None:
        self.stage = Target("Stage", True, [backdrop or backdrop_costume("backdrop1")])
        self.sprites: list[Target] = []

    def sprite(
        self,
        name: str,
        *,
        costume: Costume | list[Costume],
        x: float = 0,
        y: float = 0,
        size: float = 100,
        direction: float = 90,
        visible: bool = True,
        draggable: bool = False,
        rotation_style: str = "all around",
    ) -> Target:
        if name == "Stage" or any(s.name == name for s in self.sprites):
            raise ValueError(f"a target named {name!r} already exists")
        costumes = costume if isinstance(costume, list) else [costume]
        target = Target(
            name,
            False,
            costumes,
            properties={
                "visible": visible,
                "x": x,
                "y": y,
                "size": size,
                "direction": direction,
                "draggable": draggable,
                "rotationStyle": rotation_style,
            },
        )
        self.sprites.append(target)
        return target

    def to_project_json(self) -> dict[str, Any]:
        return _Serializer(self).project()

    def to_sb3(self) -> bytes:
        """The project as .sb3 bytes (a zip of project.json plus costume assets)."""
        files = {"project.json": json.dumps(self.to_project_json(), separators=(",", ":")).encode("utf-8")}
        for target in [self.stage, *self.sprites]:
            for costume in target.costumes:
                files[f"{costume.asset_id}.svg"] = costume.data
        buffer = io.BytesIO()
        with zipfile.ZipFile(buffer, "w", zipfile.ZIP_DEFLATED) as archive:
            for name in sorted(files):
                info = zipfile.ZipInfo(name, date_time=(1980, 1, 1, 0, 0, 0))
                info.compress_type = zipfile.ZIP_DEFLATED
                archive.writestr(info, files[name])
        return buffer.getvalue()


def _slug(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9]+", "_", text).strip("_") or "x"


class _Serializer:
    """Turns the builder's objects into project.json, allocating stable ids."""

    def __init__(self, project: Project) -> None:
        self.project_ = project
        self.broadcasts: dict[str, str] = {}
        self.counter = 0
        self.blocks: dict[str, dict[str, Any]] = {}
        self.target: Target = project.stage
        self.extensions: set[str] = set()

    def project(self) -> dict[str, Any]:
        targets = [
            self.serialize_target(t, layer) for layer, t in enumerate([self.project_.stage, *self.project_.sprites])
        ]
        targets[0]["broadcasts"] = {bid: name for name, bid in self.broadcasts.items()}
        return {
            "targets": targets,
            "monitors": [],
            "extensions": sorted(self.extensions),
            "meta": {"semver": "3.0.0", "vm": "0.2.0", "agent": "scratchworld_dist project builder"},
        }

    def var_id(self, kind: str, name: str) -> str:
        for owner in (self.target, self.project_.stage):
            pool = owner.variables if kind == "variable" else owner.lists
            if name in pool:
                return f"{kind}-{_slug(owner.name)}-{_slug(name)}"
        raise ValueError(f"{self.target.name}: no {kind} named {name!r} in the sprite or on the stage")

    def broadcast_id(self, name: str) -> str:
        return self.broadcasts.setdefault(name, f"broadcast-{_slug(name)}")

    def new_id(self) -> str:
        self.counter += 1
        return f"{_slug(self.target.name)}-{self.counter}"

    def serialize_target(self, target: Target, layer: int) -> dict[str, Any]:
        self.target = target
        self.blocks = {}
        for script in target.scripts:
            self.stack(script.blocks, parent=None, top=(script.x, script.y))
        data: dict[str, Any] = {
            "isStage": target.is_stage,
            "name": target.name,
            "variables": {self.var_id("variable", n): [n, v] for n, v in target.variables.items()},
            "lists": {self.var_id("list", n): [n, items] for n, items in target.lists.items()},
            "broadcasts": {},
            "blocks": self.blocks,
            "comments": {},
            "currentCostume": 0,
            "costumes": [
                {
                    "assetId": c.asset_id,
                    "name": c.name,
                    "bitmapResolution": 1,
                    "md5ext": f"{c.asset_id}.svg",
                    "dataFormat": "svg",
                    "rotationCenterX": c.rotation_center[0],
                    "rotationCenterY": c.rotation_center[1],
                }
                for c in target.costumes
            ],
            "sounds": [],
            "volume": 100,
            "layerOrder": layer,
        }
        if target.is_stage:
            data.update(tempo=60, videoTransparency=50, videoState="on", textToSpeechLanguage=None)
        else:
            data.update(target.properties)
        return data

    def stack(self, blocks: list[Block], parent: str | None, top: tuple[int, int] | None = None) -> str:
        ids = [self.new_id() for _ in blocks]
        for i, (block_id, item) in enumerate(zip(ids, blocks, strict=True)):
            if not isinstance(item, Block):
                raise ValueError(f"a stack holds blocks, got {item!r}")
            self.emit(
                block_id,
                item,
                parent=ids[i - 1] if i else parent,
                next_id=ids[i + 1] if i + 1 < len(ids) else None,
                top=top if i == 0 else None,
            )
        return ids[0]

    def emit(
        self, block_id: str, item: Block, parent: str | None, next_id: str | None, top: tuple[int, int] | None
    ) -> None:
        shape = SHAPES[item.opcode]
        prefix = item.opcode.split("_", 1)[0]
        if prefix in EXTENSIONS:
            self.extensions.add(prefix)
        record: dict[str, Any] = {
            "opcode": item.opcode,
            "next": next_id,
            "parent": parent,
            "inputs": {},
            "fields": {},
            "shadow": False,
            "topLevel": top is not None,
        }
        if top is not None:
            record["x"], record["y"] = top
        self.blocks[block_id] = record
        for name, value in item.args.items():
            if value == []:
                continue  # an empty C-slot is simply absent
            if name in shape.fields:
                record["fields"][name] = self.field_value(name, value)
            else:
                record["inputs"][name] = self.input_value(block_id, shape.inputs[name], name, value)
        if item.opcode == "control_stop":
            # The editor needs to know whether blocks may follow ("other scripts in sprite").
            has_next = "true" if item.args["STOP_OPTION"] == "other scripts in sprite" else "false"
            record["mutation"] = {"tagName": "mutation", "children": [], "hasnext": has_next}

    def field_value(self, name: str, value: Arg) -> list[Any]:
        if not isinstance(value, str | int | float):
            raise ValueError(f"field {name} takes a literal, got {value!r}")
        text = str(value)
        if name == "VARIABLE":
            return [text, self.var_id("variable", text)]
        if name == "LIST":
            return [text, self.var_id("list", text)]
        if name == "BROADCAST_OPTION":
            return [text, self.broadcast_id(text)]
        return [text, None]

    def input_value(self, block_id: str, slot: Slot, name: str, value: Arg) -> list[Any]:
        if slot.kind == "stack":
            if not isinstance(value, list):
                raise ValueError(f"{name} takes a list of blocks")
            return [2, self.stack(value, parent=block_id)]
        if slot.kind == "boolean":
            if not isinstance(value, Block):
                raise ValueError(f"{name} takes a boolean block")
            return [2, self.reporter(block_id, value)]
        if isinstance(value, list):
            raise ValueError(f"{name} takes a value, not a stack")
        if slot.kind == "broadcast":
            if not isinstance(value, str):
                raise ValueError(f"{name} takes a message name")
            return [1, [11, value, self.broadcast_id(value)]]
        if isinstance(value, Block):
            return [3, self.reporter(block_id, value), self.shadow(block_id, slot, slot.default)]
        return [1, self.shadow(block_id, slot, value)]

    def shadow(self, parent: str, slot: Slot, value: int | float | str) -> Any:
        if slot.kind == "primitive":
            return [PRIMITIVE_CODES[slot.shadow], str(value)]
        shadow_id = self.new_id()
        self.blocks[shadow_id] = {
            "opcode": slot.shadow,
            "next": None,
            "parent": parent,
            "inputs": {},
            "fields": {slot.menu_field: [str(value), None]},
            "shadow": True,
            "topLevel": False,
        }
        return shadow_id

    def reporter(self, parent: str, item: Block) -> Any:
        # Variable and list reporters use the compact form the editor itself writes.
        if item.opcode == "data_variable":
            name = str(item.args["VARIABLE"])
            return [12, name, self.var_id("variable", name)]
        if item.opcode == "data_listcontents":
            name = str(item.args["LIST"])
            return [13, name, self.var_id("list", name)]
        reporter_id = self.new_id()
        self.emit(reporter_id, item, parent=parent, next_id=None, top=None)
        return reporter_id
