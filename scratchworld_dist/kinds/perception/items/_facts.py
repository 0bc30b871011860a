"""What one view of the workspace shows, as the page measured it (``perceptionFacts``), and how well.

A generated item is asked only about what can be seen well: a block is *well visible* when at least
``WELL_VISIBLE`` of its own body shows (its children's area aside), *readable* when its label shows
whole at a legible size, and *unreadable* when most of its label is hidden. Answers of YES rest on
blocks that are well visible (and readable, where a kind is named); answers of NO on nothing of the
kind being in the visible area at all. What falls in between is not asked: its label would be a guess.
"""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, PrivateAttr

WELL_VISIBLE = 0.30
"""Share of a block's own body that must show for a question to be asked about it."""

CLEAR = 0.90
"""Share of the body above which a visible block counts as clear (below it: occluded)."""

READABLE = 0.90
"""Share of a block's label (its own words and icons) that must show for its words to be read."""

UNREADABLE = 0.40
"""Share of the label below which its words cannot be read (only the block's colour tells its category)."""

MIN_TEXT_PX = 7.0
"""Label text shorter than this (page px, at a small zoom) is not legible."""

FIELD_VISIBLE = 0.95
"""Share of a field's box that must show for its value to be read."""

MIN_POINTS = 4
"""A body sampled at fewer points (a sliver in view) tells too little to grade."""


class Rect(BaseModel):
    """Page pixels: top-left corner and size."""

    model_config = ConfigDict(frozen=True, extra="ignore")

    x: float
    y: float
    width: float
    height: float

    @property
    def right(self) -> float:
        return self.x + self.width

    @property
    def bottom(self) -> float:
        return self.y + self.height

    def intersects(self, other: Rect) -> bool:
        return self.x < other.right and other.x < self.right and self.y < other.bottom and other.y < self.bottom

    def overlap_x(self, other: Rect) -> float:
        """Pixels the two share along x (negative: the gap between them)."""
        return min(self.right, other.right) - max(self.x, other.x)


class Point(BaseModel):
    model_config = ConfigDict(frozen=True, extra="ignore")

    x: float
    y: float


class Seen(BaseModel):
    """Sample points that showed (``seen``) of those that count (``points``)."""

    model_config = ConfigDict(frozen=True, extra="ignore")

    seen: int = Field(ge=0)
    points: int = Field(ge=0)

    @property
    def share(self) -> float:
        return self.seen / self.points if self.points else 0.0


class LabelFacts(BaseModel):
    """A block's own words and icons as drawn (not its values)."""

    model_config = ConfigDict(frozen=True, extra="ignore")

    text: str = Field(max_length=400)
    seen: int = Field(ge=0)
    points: int = Field(ge=0)
    height: float | None = None
    """Height of its shortest text, page px."""

    @property
    def share(self) -> float:
        return self.seen / self.points if self.points else 0.0


FieldKind = Literal["number", "text", "dropdown", "other"]


class FieldFacts(BaseModel):
    """A value a block shows: its own dropdown, or the shadow in one of its inputs."""

    model_config = ConfigDict(frozen=True, extra="ignore")

    name: str = Field(max_length=200)
    """The block's field (``VARIABLE``) or the input holding the shadow (``STEPS``)."""

    kind: FieldKind
    text: str = Field(max_length=400)
    """The value as the editor names it (a dropdown's option text, ``random position``)."""

    shown: str | None = Field(default=None, max_length=400)
    """What is drawn (differs from ``text`` when the editor shortens a long value)."""

    rect: Rect
    visibility: Seen
    options: list[str] | None = Field(default=None, max_length=100)
    """A dropdown's choices as the editor names them."""


InputKind = Literal["statement", "value", "boolean", "other"]


class InputFacts(BaseModel):
    model_config = ConfigDict(frozen=True, extra="ignore")

    name: str = Field(max_length=200)
    kind: InputKind
    block: str | None = None
    """The non-shadow block in it, if any."""


class BlockFacts(BaseModel):
    """One non-shadow block of the view."""

    model_config = ConfigDict(frozen=True, extra="ignore")

    id: str
    opcode: str = Field(max_length=200)
    parent: str | None = None
    input: str | None = None
    """The parent's input it sits in; None when it hangs below its parent (or is top-level)."""

    next: str | None = None
    xy: Point
    """Its origin in workspace units (a top-level block's position in the project)."""

    rect: Rect
    """Its own body (not its children, not the blocks below it)."""

    reporter: bool = False
    body: Seen
    top: Seen
    """The top band of the body, where it joins the block above."""

    bottom: Seen
    label: LabelFacts
    fields: list[FieldFacts] = Field(default_factory=list, max_length=100)
    inputs: list[InputFacts] = Field(default_factory=list, max_length=100)

    @property
    def well_visible(self) -> bool:
        return self.body.points >= MIN_POINTS and self.body.share >= WELL_VISIBLE

    @property
    def readable(self) -> bool:
        height = self.label.height
        return self.label.points > 0 and self.label.share >= READABLE and height is not None and height >= MIN_TEXT_PX

    @property
    def unreadable(self) -> bool:
        small = self.label.height is not None and self.label.height < MIN_TEXT_PX
        return small or self.label.share <= UNREADABLE

    @property
    def hidden(self) -> bool:
        """Nothing of it showed at any sample point."""
        return self.body.seen == 0 and self.label.seen == 0

    def field(self, name: str) -> FieldFacts | None:
        return next((f for f in self.fields if f.name == name), None)

    def input_named(self, name: str) -> InputFacts | None:
        return next((i for i in self.inputs if i.name == name), None)


class ViewFacts(BaseModel):
    """Every non-shadow block of the editing target, as the view shows it."""

    model_config = ConfigDict(frozen=True, extra="ignore")

    target: str | None
    stage: bool = False
    area: Rect
    """The visible workspace (right of the palette, without scrollbars), page px."""

    palette: Rect | None = None
    """The palette (flyout), drawn translucent over the workspace: blocks under it show faintly."""

    scale: float = Field(gt=0)
    origin: Point | None = None
    """The workspace SVG's top-left corner, page px (a view's scroll names the workspace point there)."""

    blocks: list[BlockFacts] = Field(max_length=5000)
    truncated: bool = False
    """The target has more blocks than the page reports; a view of it is not used."""

    ms: float = 0
    _index: dict[str, BlockFacts] | None = PrivateAttr(default=None)

    def block(self, block_id: str) -> BlockFacts | None:
        return self._by_id().get(block_id)

    def in_view(self, block: BlockFacts) -> bool:
        """Whether any of its body lies where it could be seen: the visible area (shown or covered) or under
        the translucent palette."""
        return block.rect.intersects(self.area) or self.under_palette(block)

    def under_palette(self, block: BlockFacts) -> bool:
        return self.palette is not None and block.rect.intersects(self.palette)

    def ancestors(self, block: BlockFacts) -> list[BlockFacts]:
        """Its parent, the parent's parent... up to its script's top."""
        found: list[BlockFacts] = []
        current = block
        while current.parent is not None and len(found) < len(self.blocks):
            parent = self.block(current.parent)
            if parent is None:
                break
            found.append(parent)
            current = parent
        return found

    def in_mouth(self, block: BlockFacts) -> bool:
        """Whether its stack sits in a C-block's mouth (its first block hangs in a statement input)."""
        current = block
        for parent in self.ancestors(block):
            if current.input is not None:
                slot = parent.input_named(current.input)
                return slot is not None and slot.kind == "statement"
            current = parent
        return False

    def _by_id(self) -> dict[str, BlockFacts]:
        if self._index is None:
            self._index = {block.id: block for block in self.blocks}
        return self._index
