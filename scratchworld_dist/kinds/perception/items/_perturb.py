"""Views that make the hard cases, as changes to a project's scripts (and one to the view alone).

From the plain view's facts (where each block is, in workspace units) each change is computed on
project.json, so the saved project of a view holds it:

- ``pull_off``: a block and the blocks below it are cut off the block above and left touching or
  overlapping it, shifted sideways (a stack that only looks joined: ``connection_no_hard``);
- ``cover``: one script is laid over part of another (or, in a one-script target, the lower half of the
  script over its upper half), drawn on top; first over the left part, where blocks have their words, so that
  some blocks are told by their colour only (``existence_yes_unidentifiable``), else at other points;
- ``beside_slot``: a reporter is taken out of its slot and left lying over the block, beside the slot;
- ``cut``: no change to the project; the view is scrolled so that the workspace's right edge cuts off the
  right part of the widest script (its blocks keep their words: occluded but readable). The left edge is
  not used: the palette is translucent, and blocks under it stay faintly visible;
- ``zoom_out``: no change to the project; the view zoomed out (``ZOOM_OUT``) around the scripts, until the
  blocks' words are too small to read and only their colours tell their categories.

Blockly bumps apart scripts whose free connections come within its snap radius after every render, by a
random offset, so a change that lands a connection that close would not give the same screenshot twice.
Each change therefore comes with a few placements (``Perturbation.attempts``); the caller keeps the first
whose scripts are where the project says after loading (``bumped`` lists those that moved).
"""

from __future__ import annotations

import copy
import random
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Literal

from scratchworld_dist.kinds.perception.items._facts import BlockFacts, Rect, ViewFacts
from scratchworld_dist.kinds.perception.items._names import kind_name
from scratchworld_dist.sb3.editing import detach
from workers.contract import DragView

ChangeKind = Literal["pull_off", "cover", "beside_slot"]

SIDEWAYS = (56.0, -56.0, 72.0, 96.0)
"""Workspace units a pulled-off stack is shifted: beyond the snap radius (48), so no bump joins them back."""

LEFT_COVER = 0.35
"""Share of the covered script's width (from its left, where blocks have their words) a covering script hides
in its first placement."""

OVER = ((0.45, 0.30), (0.30, 0.55), (0.60, 0.15), (0.20, 0.75))
"""Where else a covering script's top-left corner lands on the covered one, as shares of its width and height."""

BESIDE = ((56.0, 0.0), (72.0, 6.0), (56.0, 18.0), (90.0, 0.0))
"""Offsets (units) of a reporter left beside its former slot."""

CUT = 0.62
"""Share of the widest script's width (from its left) left in view by the ``cut`` view."""

ZOOM_OUT = 0.3
"""The zoomed-out view's scale: words 12 * 0.3 / 0.675 = 5.3 px tall, under ``MIN_TEXT_PX``."""

TOLERANCE = 0.5
"""Workspace units a script may be off its saved position without counting as bumped."""


@dataclass(frozen=True)
class Perturbation:
    """One change to a target's scripts, in several placements to try in turn."""

    kind: ChangeKind
    change: str
    """The change in words, for ``PerceptionView.change``."""

    attempts: tuple[dict[str, Any], ...]
    """The target's blocks after the change, one per placement."""


def perturbations(blocks: Mapping[str, Any], facts: ViewFacts, rng: random.Random) -> list[Perturbation]:
    """The changes this target allows, computed from its blocks and the plain view's facts."""
    found = [_pull_off(blocks, facts, rng), _cover(blocks, facts, rng), _beside_slot(blocks, facts, rng)]
    return [p for p in found if p is not None]


def cut_view(view: DragView, facts: ViewFacts) -> DragView | None:
    """``view`` scrolled so that the workspace's right edge cuts the widest script at ``CUT`` of its width, or
    None when no script is wide enough to be cut in a telling place."""
    scripts = [_extent(facts, top) for top in _tops(facts)]
    if not scripts:
        return None
    widest = max(scripts, key=lambda r: (r.width, -r.y))
    if widest.width * (1 - CUT) < 24:
        return None
    shift = widest.x + CUT * widest.width - facts.area.right
    return view.model_copy(update={"scroll_x": round(view.scroll_x + shift / facts.scale, 3)})


def zoom_view(view: DragView, facts: ViewFacts) -> DragView | None:
    """``view`` zoomed out to ``ZOOM_OUT``, the scripts' middle kept in the middle of the visible area."""
    scripts = [_extent(facts, top) for top in _tops(facts)]
    if not scripts or facts.origin is None:
        return None
    content = _union(scripts)
    middle = (content.x + content.width / 2, content.y + content.height / 2)
    centre = (facts.area.x + facts.area.width / 2, facts.area.y + facts.area.height / 2)
    origin = (facts.origin.x, facts.origin.y)
    scroll = [
        start + (middle[i] - origin[i]) / facts.scale - (centre[i] - origin[i]) / ZOOM_OUT
        for i, start in enumerate((view.scroll_x, view.scroll_y))
    ]
    return view.model_copy(update={"scroll_x": round(scroll[0], 3), "scroll_y": round(scroll[1], 3), "scale": ZOOM_OUT})


def bumped(blocks: Mapping[str, Any], facts: ViewFacts) -> list[str]:
    """Top-level blocks of ``facts`` that are not where ``blocks`` (the project) puts them."""
    moved = []
    for block in facts.blocks:
        if block.parent is not None:
            continue
        saved = blocks.get(block.id)
        if isinstance(saved, dict):
            at = (saved.get("x"), saved.get("y"))
        elif isinstance(saved, list) and len(saved) >= 5:
            at = (saved[3], saved[4])
        else:
            at = (None, None)
        if not all(isinstance(v, int | float) for v in at):
            continue
        if abs(block.xy.x - at[0]) > TOLERANCE or abs(block.xy.y - at[1]) > TOLERANCE:  # type: ignore[operator]
            moved.append(block.id)
    return moved


def _pull_off(blocks: Mapping[str, Any], facts: ViewFacts, rng: random.Random) -> Perturbation | None:
    links = [
        (upper, lower) for lower in facts.blocks
        if lower.parent is not None and lower.input is None and not lower.reporter and lower.well_visible
        and (upper := facts.block(lower.parent)) is not None and upper.well_visible
    ]  # fmt: skip
    if not links:
        return None
    upper, lower = rng.choice(links)
    attempts = tuple(
        _last(
            detach(blocks, reference=upper.id, moved=lower.id, input_name=None, at=(lower.xy.x + dx, lower.xy.y)),
            lower.id,
        )
        for dx in SIDEWAYS
    )
    change = f"{_called(lower)} and the blocks below it were pulled off {_called(upper)} and left touching it, shifted"
    return Perturbation("pull_off", f"{change} sideways", attempts)


def _cover(blocks: Mapping[str, Any], facts: ViewFacts, rng: random.Random) -> Perturbation | None:
    tops = [top for top in _tops(facts) if isinstance(blocks.get(top.id), dict)]
    if len(tops) >= 2:
        covered = max(tops, key=lambda t: (_extent(facts, t).width * _extent(facts, t).height, t.id))
        mover = rng.choice([t for t in tops if t.id != covered.id])
        shifts = _over(facts, _extent(facts, mover), _extent(facts, covered))
        attempts = tuple(_last(_moved(blocks, mover.id, mover, shift), mover.id) for shift in shifts)
        change = f"the script of {_called(mover)} was laid over the script of {_called(covered)}"
        return Perturbation("cover", change, attempts)
    chain = _chain(facts, tops[0]) if tops else []
    if len(chain) < 3:
        return None
    upper, lower = chain[len(chain) // 2 - 1], chain[len(chain) // 2]
    below = {b.id for b in _script(facts, lower)}
    rest = _union([b.rect for b in _script(facts, tops[0]) if b.id not in below])
    attempts = tuple(
        _last(
            detach(
                blocks, reference=upper.id, moved=lower.id, input_name=None,
                at=(lower.xy.x + dx, lower.xy.y + dy),
            ),
            lower.id,
        )
        for dx, dy in _over(facts, _extent(facts, lower), rest)
    )  # fmt: skip
    change = f"the script was cut below {_called(upper)} and its lower part laid over its upper part"
    return Perturbation("cover", change, attempts)


def _over(facts: ViewFacts, mover: Rect, covered: Rect) -> list[tuple[float, float]]:
    """Shifts (workspace units) that lay ``mover`` over ``covered`` (page px): first over its left part, where
    the words are (leaving blocks told by colour only), then at the ``OVER`` points."""
    targets = [(covered.x + LEFT_COVER * covered.width - mover.width, covered.y + 0.3 * covered.height)]
    targets += [(covered.x + fx * covered.width, covered.y + fy * covered.height) for fx, fy in OVER]
    return [((x - mover.x) / facts.scale, (y - mover.y) / facts.scale) for x, y in targets]


def _beside_slot(blocks: Mapping[str, Any], facts: ViewFacts, rng: random.Random) -> Perturbation | None:
    reporters = [
        (parent, block) for block in facts.blocks
        if block.reporter and block.input is not None and block.well_visible and isinstance(blocks.get(block.id), dict)
        and (parent := facts.block(block.parent or "")) is not None and parent.well_visible
        and (slot := parent.input_named(block.input)) is not None and slot.kind in ("value", "boolean")
    ]  # fmt: skip
    if not reporters:
        return None
    parent, reporter = rng.choice(reporters)
    attempts = tuple(
        _last(
            detach(
                blocks, reference=parent.id, moved=reporter.id, input_name=reporter.input,
                at=(reporter.xy.x + dx, reporter.xy.y + dy),
            ),
            reporter.id,
        )
        for dx, dy in BESIDE
    )  # fmt: skip
    change = f"{_called(reporter)} was taken out of its slot in {_called(parent)} and left lying beside the slot"
    return Perturbation("beside_slot", change, attempts)


def _tops(facts: ViewFacts) -> list[BlockFacts]:
    """Top-level blocks with some of their script in the visible area."""
    return [b for b in facts.blocks if b.parent is None and _extent(facts, b).intersects(facts.area)]


def _script(facts: ViewFacts, top: BlockFacts) -> list[BlockFacts]:
    return [b for b in facts.blocks if b.id == top.id or top.id in {a.id for a in facts.ancestors(b)}]


def _extent(facts: ViewFacts, top: BlockFacts) -> Rect:
    return _union([b.rect for b in _script(facts, top)])


def _chain(facts: ViewFacts, top: BlockFacts) -> list[BlockFacts]:
    """The script's own stack: its top and the blocks hanging below it, not those in mouths or slots."""
    chain = [top]
    while chain[-1].next is not None and (following := facts.block(chain[-1].next)) is not None:
        chain.append(following)
        if len(chain) > len(facts.blocks):
            break
    return chain


def _union(rects: list[Rect]) -> Rect:
    x, y = min(r.x for r in rects), min(r.y for r in rects)
    return Rect(x=x, y=y, width=max(r.right for r in rects) - x, height=max(r.bottom for r in rects) - y)


def _moved(blocks: Mapping[str, Any], top: str, block: BlockFacts, shift: tuple[float, float]) -> dict[str, Any]:
    """``blocks`` with the script at ``top`` (shown as ``block``) shifted by ``shift`` workspace units."""
    moved = dict(blocks)
    at = (round(block.xy.x + shift[0]), round(block.xy.y + shift[1]))
    moved[top] = {**copy.deepcopy(blocks[top]), "x": at[0], "y": at[1]}
    return moved


def _last(blocks: dict[str, Any], top: str) -> dict[str, Any]:
    """``blocks`` with the script at ``top`` listed last, so that the editor draws it over the others."""
    mine: list[str] = []
    todo = [top]
    while todo:
        current = todo.pop()
        block = blocks.get(current)
        if current in mine or not isinstance(block, dict):
            continue
        mine.append(current)
        following = block.get("next")
        todo += [following] if isinstance(following, str) else []
        for entry in (block.get("inputs") or {}).values():
            todo += [ref for ref in entry[1:3] if isinstance(ref, str)] if isinstance(entry, list) else []
    chosen = set(mine)
    return {**{k: v for k, v in blocks.items() if k not in chosen}, **{k: blocks[k] for k in mine}}


def _called(block: BlockFacts) -> str:
    name = kind_name(block.opcode)
    return f"`{name}`" if name else f"a {block.opcode} block"
