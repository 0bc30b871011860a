"""What a drag task needs to know about its project: targets in sprite-pane order and their blocks.

Read from project.json with the same checks a worker applies before loading a project
(``check_project``), so a task whose project would be refused fails here, at load time.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from scratchworld_dist._errors import ProjectFormatError
from scratchworld_dist._files import MIB, FileTooLargeError, read_file
from scratchworld_dist.sb3 import check_project
from workers.contract import ProjectLimits

_TOP_LEVEL_REPORTERS = {12: "data_variable", 13: "data_listcontents"}
"""Compact codes of reporters stored as lists in ``blocks`` (a variable or list dropped on the canvas)."""

_OPCODE_CATEGORIES = {
    "motion": "motion",
    "looks": "looks",
    "sound": "sound",
    "event": "events",
    "control": "control",
    "sensing": "sensing",
    "operator": "operators",
    "data": "variables",
    "procedures": "myBlocks",
}


def palette_category_of(opcode: str) -> str | None:
    """The palette category that offers ``opcode`` (``data_*`` -> variables), or None for extensions."""
    return _OPCODE_CATEGORIES.get(opcode.split("_", 1)[0])


@dataclass(frozen=True)
class ProjectTarget:
    name: str
    is_stage: bool
    blocks: Mapping[str, Any]

    @property
    def label(self) -> str:
        """How messages name it."""
        return "the Stage" if self.is_stage else f"sprite {self.name!r}"


@dataclass(frozen=True)
class ProjectIndex:
    """The targets of one project, in the order project.json lists them."""

    targets: tuple[ProjectTarget, ...]

    @classmethod
    def from_json(cls, project: Mapping[str, Any]) -> ProjectIndex:
        targets = []
        for target in project["targets"]:
            blocks = target.get("blocks") if isinstance(target, dict) else None
            name = target.get("name") if isinstance(target, dict) else None
            targets.append(
                ProjectTarget(
                    name=name if isinstance(name, str) else "",
                    is_stage=bool(target.get("isStage")) if isinstance(target, dict) else False,
                    blocks=blocks if isinstance(blocks, dict) else {},
                )
            )
        return cls(tuple(targets))

    @property
    def sprites(self) -> tuple[ProjectTarget, ...]:
        """Sprites in sprite-pane order: the VM sorts targets back into project.json order on load."""
        return tuple(t for t in self.targets if not t.is_stage)

    @property
    def stage(self) -> ProjectTarget | None:
        return next((t for t in self.targets if t.is_stage), None)

    def default_target(self) -> ProjectTarget | None:
        """The target the editor shows after loading: the VM picks ``targets[1]`` when there are two or more."""
        if not self.targets:
            return None
        return self.targets[1] if len(self.targets) > 1 else self.targets[0]

    def sprite(self, name: str) -> ProjectTarget | None:
        return next((t for t in self.sprites if t.name == name), None)

    def holder(self, block_id: str) -> ProjectTarget | None:
        """The target whose scripts contain ``block_id``."""
        return next((t for t in self.targets if block_id in t.blocks), None)

    def opcode(self, block_id: str) -> str | None:
        target = self.holder(block_id)
        if target is None:
            return None
        block = target.blocks[block_id]
        if isinstance(block, dict):
            opcode = block.get("opcode")
            return opcode if isinstance(opcode, str) else None
        if isinstance(block, list) and block and isinstance(block[0], int):
            return _TOP_LEVEL_REPORTERS.get(block[0])
        return None

    def stack_tail(self, block_id: str) -> str:
        """The last block of the stack that starts at ``block_id`` (what moves with it when dragged)."""
        target = self.holder(block_id)
        if target is None:
            return block_id
        seen = {block_id}
        current = block_id
        while True:
            block = target.blocks.get(current)
            following = block.get("next") if isinstance(block, dict) else None
            if not isinstance(following, str) or following in seen or following not in target.blocks:
                return current
            seen.add(following)
            current = following


def read_project_index(path: Path, limits: ProjectLimits | None = None) -> ProjectIndex:
    """The project at ``path``, checked as a worker would; raises ``OSError`` or ``ProjectFormatError``."""
    limits = limits or ProjectLimits()
    try:
        data = read_file(path, int(limits.max_file_mb * MIB))
    except FileTooLargeError as exc:
        raise ProjectFormatError(f"the project is {exc.strerror}, over project_limits.max_file_mb") from exc
    return ProjectIndex.from_json(check_project(data, limits))
