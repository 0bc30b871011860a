"""Single-step drag tasks made from any project: every connection in its scripts, cut and asked back.

Cutting one connection (a stack from the block above it, a stack from a C-block's mouth, a reporter
from its slot) and asking for it back gives a task whose answer is exact, in a project that is
otherwise its author's; deleting the cut block instead makes the same connection a drag from the
palette. Views (scroll, zoom) are chosen later, in a browser.
"""

from __future__ import annotations

import hashlib
import json
import random
import re
from collections import Counter, defaultdict
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator, model_validator

from scratchworld_dist._errors import ProjectFormatError, validation_summary
from scratchworld_dist.kinds.drag.items._instruction import instruction
from scratchworld_dist.kinds.drag.items._project import palette_category_of
from scratchworld_dist.kinds.drag.items._task import DragTask
from scratchworld_dist.sb3 import Sb3Archive, check_project
from scratchworld_dist.sb3.editing import (
    COMPACT_REPORTERS,
    ScriptLink,
    block_label,
    cut_link,
    palette_label,
    palette_offers,
    stack_tail,
)
from scratchworld_dist.suites import task_id_problem
from workers.contract import ConnectionKind, DragView, PaletteCategory
from workers.kinds.drag import CONNECTIONS_OF, CanvasSource, DragSource, DragType, ExpectedConnection, FlyoutSource

_SUBSTACKS: dict[str, ConnectionKind] = {"SUBSTACK": "substack_1", "SUBSTACK2": "substack_2"}


@dataclass(frozen=True)
class GenerationProblem:
    """A part of a project no task was made from, and why (one line)."""

    project: str
    message: str

    def __post_init__(self) -> None:
        object.__setattr__(self, "message", " ".join(self.message.split())[:300])


class DragCandidate(BaseModel):
    """One connection of a project, cut: a drag task but for its view, which a browser pass decides."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    id: str
    project_name: str
    type: DragType
    project: bytes = Field(repr=False)
    """The original project with the connection cut (.sb3, or JSON when the original was bare JSON)."""

    source: DragSource
    detached_block_id: str | None
    """The cut block's id in the original project; None for a variable reporter stored compactly there."""

    reference_block_id: str = Field(min_length=1)
    reference_opcode: str = Field(min_length=1)
    connection: ExpectedConnection
    instruction: str = Field(min_length=1)
    description: str = ""
    sprite: str | None
    """The sprite holding the blocks; None for the Stage."""

    category: PaletteCategory | None = None
    """The palette category offering a flyout source."""

    show_block_ids: tuple[str, ...]
    """The view must show these: the reference's top block, and the source's for a canvas source."""

    ambiguous: bool = False
    """Another block of the sprite shows the same text as the reference or the canvas source."""

    @field_validator("id")
    @classmethod
    def _plain_id(cls, value: str) -> str:
        if (problem := task_id_problem(value)) is not None:
            raise ValueError(problem)
        return value

    @model_validator(mode="after")
    def _consistent(self) -> DragCandidate:
        if self.connection.kind not in CONNECTIONS_OF[self.type]:
            raise ValueError(f"a {self.type} candidate cannot connect by {self.connection.kind!r}")
        if isinstance(self.source, FlyoutSource) and self.category is None:
            raise ValueError("a flyout source needs its palette category")
        return self

    def task(self, initial_project: Path, view: DragView) -> DragTask:
        """The drag task, once its project is saved at ``initial_project`` and its view is chosen."""
        fields = {"id", "type", "instruction", "description", "source", "reference_block_id", "reference_opcode"}
        parts = {name: getattr(self, name) for name in (*fields, "connection")}
        return DragTask(**parts, initial_project=initial_project, view=view)


class _ScriptError(Exception):
    """A script that is not consistent enough to cut."""


@dataclass(frozen=True)
class _Target:
    index: int
    sprite: str | None
    blocks: Mapping[str, Any]
    label: str
    counts: Counter[str]


def drag_candidates(sb3: bytes, *, project_name: str) -> tuple[list[DragCandidate], list[GenerationProblem]]:
    """Every connection of every script of ``sb3`` as a canvas candidate, plus a palette variant for
    each single block the palette offers; what cannot be cut is a problem, never an exception."""
    try:
        project = check_project(sb3)
    except ProjectFormatError as exc:
        return [], [GenerationProblem(project_name, f"not a usable project: {exc}")]
    problems: list[GenerationProblem] = []
    sprites = [t for t in project["targets"] if isinstance(t, dict) and not t.get("isStage")]
    names = Counter(t["name"] for t in sprites if isinstance(t.get("name"), str))
    archive = Sb3Archive(sb3)
    candidates: list[DragCandidate] = []
    stage_seen = False
    for index, raw in enumerate(project["targets"]):
        if not isinstance(raw, dict) or not isinstance(raw.get("blocks"), dict):
            problems.append(GenerationProblem(project_name, f"target #{index} is not a target with blocks"))
            continue
        name = raw.get("name")
        if raw.get("isStage"):
            label, sprite, clash = "the Stage", None, stage_seen
            stage_seen = True
        else:
            label, sprite = f"sprite {name!r}", name
            clash = not isinstance(name, str) or not name or names[name] > 1
        if clash:
            problems.append(GenerationProblem(project_name, f"{label}: not unique by name, so no view can select it"))
            continue
        blocks = raw["blocks"]
        counts = Counter(
            block_label(blocks, bid) for bid, b in blocks.items() if isinstance(b, dict) and not b.get("shadow")
        )
        target = _Target(index, sprite, blocks, label, counts)
        for link in _links(target, project_name, problems):
            single = link.moved is not None and link.tail == link.moved
            for flyout in (False, True) if single and palette_offers(blocks, link.moved, sprite is None) else (False,):
                try:
                    candidates.append(_candidate(project_name, project, archive, target, link, flyout))
                except ValidationError as exc:
                    why = f"{label}: {link.kind} at {link.reference!r}: {validation_summary(exc)}"
                    problems.append(GenerationProblem(project_name, why))
    return candidates, problems


def _links(target: _Target, project_name: str, problems: list[GenerationProblem]) -> list[ScriptLink]:
    blocks = target.blocks
    seen: set[str] = set()
    links: list[ScriptLink] = []
    for top, block in blocks.items():
        if not isinstance(block, dict) or not block.get("topLevel"):
            continue
        try:
            links += _scan(blocks, top, seen)
        except _ScriptError as exc:
            problems.append(GenerationProblem(project_name, f"{target.label}: script {top!r} skipped: {exc}"))
    return links


def _scan(blocks: Mapping[str, Any], top: str, seen: set[str]) -> list[ScriptLink]:
    """The connections of the script at ``top``, checking every parent pointer on the way."""
    found: list[tuple[Any, ...]] = []
    rows: dict[str, int] = {}
    chain = {top}
    todo: list[tuple[str, str | None]] = [(top, None)]
    while todo:
        bid, parent = todo.pop()
        block = blocks.get(bid)
        if not isinstance(block, dict) or not isinstance(block.get("opcode"), str) or not block["opcode"]:
            raise _ScriptError(f"block {bid!r} is missing or has no opcode")
        if bid in seen:
            raise _ScriptError(f"block {bid!r} is reached twice")
        seen.add(bid)
        if block.get("parent") != parent:
            raise _ScriptError(f"block {bid!r} names parent {block.get('parent')!r} but hangs from {parent!r}")
        if parent is not None and block.get("topLevel"):
            raise _ScriptError(f"block {bid!r} hangs from {parent!r} but is marked top-level")
        rows[bid] = len(rows)
        following, inputs = block.get("next"), block.get("inputs", {})
        if (following is not None and not isinstance(following, str)) or not isinstance(inputs, dict):
            raise _ScriptError(f"block {bid!r} has a malformed next or inputs")
        live = not block.get("shadow") and block["opcode"] != "procedures_prototype"
        if following is not None and live:
            found.append(("next", bid, following, None, None))
            if bid in chain:
                chain.add(following)
                found.append(("parent", following, top, bid, None))
        children: list[str] = []
        for name, entry in inputs.items():
            if not isinstance(entry, list) or not entry:
                raise _ScriptError(f"block {bid!r}: input {name!r} is not a list")
            held, shadow = [*entry, None, None][1:3]
            children += [r for r in (held, shadow) if isinstance(r, str) and r not in children]
            child = blocks.get(held) if isinstance(held, str) else None
            if not live or not name or held == shadow or block["opcode"] == "procedures_definition":
                continue
            if isinstance(child, dict) and not child.get("shadow"):
                if name in _SUBSTACKS:
                    found.append((_SUBSTACKS[name], bid, held, None, name))
                elif entry[0] in (2, 3) and child.get("opcode") != "procedures_prototype":
                    found.append(("input", bid, held, None, name))
            elif _compact(held) and entry[0] in (2, 3):
                found.append(("input", bid, None, None, name, (held[0], held[1], held[2])))
        todo += [(following, bid)] if following is not None else []
        todo += [(child_id, bid) for child_id in reversed(children)]
    links = []
    for kind, reference, moved, tail, name, *compact in found:
        tail = tail or (stack_tail(blocks, moved) if moved else None)
        links.append(
            ScriptLink(kind, reference, moved, tail, top, rows[reference], name, compact[0] if compact else None)
        )
    return links


def _compact(held: Any) -> bool:
    """Whether an input holds a variable or list reporter in the compact form ``[12, name, id]``."""
    if not isinstance(held, list) or len(held) < 3 or held[0] not in COMPACT_REPORTERS:
        return False
    return isinstance(held[1], str) and bool(held[1]) and isinstance(held[2], str)


def _candidate(
    project_name: str, project: Mapping[str, Any], archive: Sb3Archive, target: _Target, link: ScriptLink, flyout: bool
) -> DragCandidate:
    before = target.blocks
    blocks, moved, comments = cut_link(before, link, flyout, project["targets"][target.index].get("comments"))
    ref = link.reference
    raw = {**project["targets"][target.index], "blocks": blocks}
    if comments is not None:
        raw["comments"] = comments
    changed = {**project, "targets": [raw if i == target.index else t for i, t in enumerate(project["targets"])]}
    opcode = before[link.moved]["opcode"] if link.moved else COMPACT_REPORTERS[link.compact[0]][0]  # type: ignore[index]
    category = palette_category_of(opcode) if flyout else None
    source: DragSource = (
        FlyoutSource(opcode=opcode)
        if flyout
        else CanvasSource(block_id=moved, opcode=opcode, tail_block_id=link.tail or moved)
    )
    ref_label, source_label = block_label(blocks, ref), block_label(blocks, moved)
    ambiguous = target.counts[ref_label] - (ref_label == block_label(before, ref)) > 0
    if not flyout:
        ambiguous |= target.counts[source_label] > (0 if link.compact else 1)
    variable = link.compact[1] if link.compact and link.compact[0] == 12 else None
    connection = ExpectedConnection(
        kind=link.kind, input_name=link.input_name if link.kind == "input" else None, variable_name=variable
    )
    key = json.dumps([project_name, target.index, link.kind, ref, link.moved, link.input_name, link.compact])
    digest = hashlib.sha256(key.encode()).hexdigest()[:10]
    slug = re.sub(r"[^A-Za-z0-9._-]+", "_", project_name).strip("._-")[:80] or "project"
    return DragCandidate(
        id=f"{slug}-{link.kind}-{digest}" + ("-flyout" if flyout else ""),
        project_name=project_name,
        type=_type_of(link.kind),
        project=archive.with_project(changed),
        source=source,
        detached_block_id=link.moved,
        reference_block_id=ref,
        reference_opcode=before[ref]["opcode"],
        connection=connection,
        instruction=instruction(
            blocks,
            ref,
            link.kind,
            link.input_name,
            source=palette_label(opcode) if flyout else source_label,
            category=category,
            stack=source.kind == "canvas" and source.tail_block_id != moved,
            variable=variable is not None,
        ),
        description=f"{project_name!r}, {target.label}: {opcode} {link.kind} {before[ref]['opcode']} "
        f"({'palette' if flyout else 'canvas'})",
        sprite=target.sprite,
        category=category,
        show_block_ids=tuple(dict.fromkeys([ref if link.kind == "parent" else link.top, *([] if flyout else [moved])])),
        ambiguous=ambiguous,
    )


_PRIORITY: tuple[tuple[ConnectionKind, str], ...] = (
    ("next", "canvas"), ("input", "flyout"), ("parent", "flyout"), ("substack_1", "canvas"), ("parent", "canvas"),
    ("substack_2", "flyout"), ("next", "flyout"), ("input", "canvas"), ("substack_1", "flyout"),
    ("substack_2", "canvas"),
)  # fmt: skip
"""Bucket order for ties: the first picks alternate type and source kind."""


def select_candidates(
    candidates: Iterable[DragCandidate], *, limit_per_project: int | None, seed: int
) -> list[DragCandidate]:
    """At most ``limit_per_project`` candidates of each project, spread over (connection kind, source
    kind) buckets in turn, then types and source kinds; the same input and seed give the same list."""
    if limit_per_project is not None and limit_per_project < 0:
        raise ValueError(f"limit_per_project must be 0 or more, not {limit_per_project}")
    by_project: dict[str, list[DragCandidate]] = defaultdict(list)
    for candidate in candidates:
        by_project[candidate.project_name].append(candidate)
    chosen: list[DragCandidate] = []
    for name in sorted(by_project):
        group = sorted(by_project[name], key=lambda c: c.id)
        if limit_per_project is None:
            chosen += group
            continue
        rng = random.Random(f"{seed}:{name}")
        buckets: dict[tuple[ConnectionKind, str], list[DragCandidate]] = {key: [] for key in _PRIORITY}
        for candidate in group:
            buckets[(candidate.connection.kind, candidate.source.kind)].append(candidate)
        for bucket in buckets.values():
            rng.shuffle(bucket)
        scarce = {_base(c) for c in group if c.source.kind == "flyout"}
        counts: Counter[Any] = Counter()
        used: set[str] = set()
        for _ in range(min(limit_per_project, len(group))):
            key = min(
                (k for k in _PRIORITY if buckets[k]),
                key=lambda k: (counts[k], counts[_type_of(k[0])] + counts[k[1]], counts[k[0]], _PRIORITY.index(k)),
            )
            bucket = buckets[key]
            pick = bucket.pop(min(range(len(bucket)), key=lambda i: _preference(bucket[i], used, scarce)))
            used.add(_base(pick))
            counts.update([key, _type_of(key[0]), key[1], key[0]])
            chosen.append(pick)
    return chosen


def _preference(candidate: DragCandidate, used: set[str], scarce: set[str]) -> tuple[bool, bool, bool]:
    """Lowest first: a connection not picked yet, not one of the few the palette offers (spent on a
    canvas source), with an unambiguous instruction."""
    base = _base(candidate)
    return base in used, candidate.source.kind == "canvas" and base in scarce, candidate.ambiguous


def _type_of(kind: ConnectionKind) -> DragType:
    return "T1" if kind in CONNECTIONS_OF["T1"] else "T2"


def _base(candidate: DragCandidate) -> str:
    return candidate.id.removesuffix("-flyout")
