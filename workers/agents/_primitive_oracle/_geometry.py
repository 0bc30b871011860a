"""Where the page draws things, typed: the replies of ``scratch-gui/geometry/`` that gestures aim by.

All positions are page pixels (CSS pixels of the viewport, as gestures take them). The page writes
camelCase keys, the models name them in snake_case. ``Page`` validates every reply against these
models (and those of ``_state``), so a reply in another shape stops the oracle at the read, not at
a missing key later.

They live beside the oracle because it is their only reader: geometry is privileged (no agent
under evaluation sees it), so it belongs neither to primitive mode nor to the contract.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Discriminator, RootModel, Tag
from pydantic.alias_generators import to_camel


class Reply(BaseModel):
    """Base of every reply model: immutable, camelCase keys on the page; extra keys are ignored."""

    model_config = ConfigDict(frozen=True, alias_generator=to_camel, populate_by_name=True)


def by_flag(key: str, true: str, false: str) -> Discriminator:
    """Picks the branch of a reply union by a boolean key (``found``, ``open``), tagged ``true`` or
    ``false``: pydantic's own discriminators would name a branch ``1`` in error messages."""

    def tag(value: Any) -> str | None:
        flag = value.get(key) if isinstance(value, dict) else getattr(value, key, None)
        return true if flag is True else false if flag is False else None

    message = f"not an object with {key} true or false"
    return Discriminator(tag, custom_error_type="no_flag", custom_error_message=message)


# ---------- points and rectangles ----------


class Point(Reply):
    """A point in page pixels: where a gesture presses or releases, a connection, a corner."""

    x: float
    y: float


class Rect(Reply):
    """An axis-aligned box in page pixels: top-left corner and size (``getBoundingClientRect``)."""

    x: float
    y: float
    width: float
    height: float

    def centre(self) -> Point:
        return Point(x=self.x + self.width / 2, y=self.y + self.height / 2)

    def contains(self, point: Point) -> bool:
        """Edges included, as the page's own ``inside``."""
        return self.x <= point.x <= self.x + self.width and self.y <= point.y <= self.y + self.height

    def corners(self) -> list[Point]:
        """Top-left and bottom-right: a box is in view when both are."""
        return [Point(x=self.x, y=self.y), Point(x=self.x + self.width, y=self.y + self.height)]

    @property
    def top_left(self) -> Point:
        return Point(x=self.x, y=self.y)

    @property
    def bottom_left(self) -> Point:
        return Point(x=self.x, y=self.y + self.height)


# ---------- blocks on the workspace (geometryBlock, geometryField) ----------


class ConnectionPoint(Point):
    """Where a block's connection is drawn; a dragged block snaps when its own one comes near it."""

    connected: bool
    """Something is attached to it."""


class InputConnection(ConnectionPoint):
    """The connection of one named input (a value slot or a C-block's mouth)."""

    kind: Literal["statement", "value", "other"]
    block: str | None
    """Id of the block in the input (a shadow counts), None when empty."""
    shadow: bool


class BlockShape(Reply):
    """Which connections the block has: decides how a drag of it may join another block."""

    hat: bool
    reporter: bool
    previous: bool
    next: bool


class Attachment(Reply):
    """Where a block hangs: under ``parent``'s next connection (``input`` None) or in its input."""

    parent: str
    input: str | None


class BlockGeometry(Reply):
    """``geometryBlock``: a workspace block as drawn, with the points a connecting drag aims at."""

    id: str
    opcode: str
    rect: Rect
    grab: Point | None
    """A point of the block's own body that a press hits, inside the safe area; None when there is none."""
    shape: BlockShape
    attachment: Attachment | None
    """None for a top-level block."""
    root: str
    """Id of the top block of its script."""
    next_block: str | None
    previous: ConnectionPoint | None
    next: ConnectionPoint | None
    output: ConnectionPoint | None
    last_next: ConnectionPoint | None
    """The next connection at the end of the stack the block starts."""
    inputs: dict[str, InputConnection]


class FieldOption(Reply):
    """One dropdown choice: what the menu shows and what the VM stores."""

    text: str
    value: str


class FieldGeometry(Reply):
    """``geometryField``: a field of a block, or the field of the shadow in one of its inputs."""

    kind: Literal["dropdown", "text", "colour"]
    """``colour``: a click opens the colour picker (``ColourPicker``)."""
    name: str
    value: str | None
    text: str
    rect: Rect | None
    """None when the field is not drawn."""
    options: list[FieldOption] | None
    """Dropdowns only (empty when the page could not list them)."""


# ---------- the palette (geometryFlyoutBlock, geometryFlyoutButton) ----------


class PaletteMiss(Reply):
    """The palette holds no such block or button (its category may not be drawn yet)."""

    found: Literal[False]
    flyout: Rect
    count: int | None = None
    """Blocks only: palette blocks of the opcode (none of them for the asked variable)."""


class FlyoutBlock(Reply):
    """A palette block to drag out; it grows from the palette's scale to the workspace's on the way."""

    found: Literal[True]
    id: str
    rect: Rect
    visible: bool
    """Wholly inside the palette's visible part."""
    grab: Point | None
    flyout: Rect
    flyout_scale: float
    workspace_scale: float

    @property
    def usable(self) -> bool:
        return self.visible and self.grab is not None


class FlyoutButton(Reply):
    """A palette button ("Make a Variable", "Make a List")."""

    found: Literal[True]
    rect: Rect
    visible: bool
    flyout: Rect

    @property
    def usable(self) -> bool:
        return self.visible


class FlyoutBlockReply(
    RootModel[
        Annotated[
            Annotated[FlyoutBlock, Tag("found")] | Annotated[PaletteMiss, Tag("missing")],
            by_flag("found", "found", "missing"),
        ]
    ]
):
    """``geometryFlyoutBlock``."""


class FlyoutButtonReply(
    RootModel[
        Annotated[
            Annotated[FlyoutButton, Tag("found")] | Annotated[PaletteMiss, Tag("missing")],
            by_flag("found", "found", "missing"),
        ]
    ]
):
    """``geometryFlyoutButton``."""


# ---------- around the workspace (geometryLayout) ----------


class Category(Reply):
    """A button of the category menu left of the palette; a click scrolls the palette to it."""

    name: str
    rect: Rect
    selected: bool


class SpriteTile(Reply):
    """A sprite's tile in the sprite pane; a click makes it the editing target."""

    name: str
    rect: Rect


class TargetTiles(Reply):
    sprites: list[SpriteTile]
    stage: Rect | None
    """The stage selector, None when it is not on the page."""


class Layout(Reply):
    """``geometryLayout``: where the workspace, the palette and the panes around them are drawn."""

    workspace: Rect
    """The visible part of the workspace."""
    safe_area: Rect
    """Where blocks may be grabbed and dropped: the workspace without its edges and scrollbars."""
    overlays: list[Rect]
    """Things drawn over the workspace (zoom buttons, watermark, workspace comments)."""
    flyout: Rect
    scale: float
    min_scale: float
    """The smallest scale the zoom-out button reaches."""
    zoom_out: Rect | None
    """The workspace's zoom-out button; None when it is not drawn."""
    snap_radius: float
    connecting_snap_radius: float
    categories: list[Category]
    targets: TargetTiles
    editing_target: str | None
    viewport: Rect


# ---------- widgets over the workspace (geometryMenu, geometryTextEditor, geometryModal) ----------


class MenuItem(Reply):
    text: str
    rect: Rect
    visible: bool
    """A press at its centre reaches it (not scrolled out of the menu)."""


class Menu(Reply):
    """``geometryMenu``: the open dropdown of a field, or a context menu."""

    open: bool
    items: list[MenuItem]
    rect: Rect | None
    """The menu's box (it scrolls when longer); None when closed."""


class TextEditor(Reply):
    """``geometryTextEditor``: the text input Blockly opens over a clicked text field."""

    open: bool
    focused: bool
    value: str | None
    rect: Rect | None = None
    """Where it is drawn (None when closed): a click there gives it the keys."""


class ColourSlider(Reply):
    """One range input of the colour picker: a click on it sets a value by position, arrow keys step it."""

    rect: Rect
    value: float
    min: float
    max: float
    step: float
    focused: bool


class ColourPicker(Reply):
    """``geometryColourPicker``: the open picker of a colour field; sliders hue, saturation, brightness."""

    open: bool
    sliders: list[ColourSlider]
    eyedropper: Rect | None = None
    """The button that lets a click on the stage pick the colour there."""


class StagePixel(Reply):
    """``geometryStagePixel``: a page point inside an area of the stage showing exactly a colour, as the
    eyedropper picks it (None when the stage shows it nowhere)."""

    found: bool
    point: Point | None
    stage: Rect


class ModalInput(Reply):
    rect: Rect
    value: str
    focused: bool


class ModalOption(Reply):
    """A radio choice of a prompt ("For all sprites", ...)."""

    text: str
    rect: Rect
    checked: bool


class ModalButton(Reply):
    text: str
    rect: Rect


class ClosedModal(Reply):
    open: Literal[False]


class OpenModal(Reply):
    """The GUI's open modal dialog (the prompts for a new variable, list or message)."""

    open: Literal[True]
    title: str
    inputs: list[ModalInput]
    options: list[ModalOption]
    buttons: list[ModalButton]


class ModalReply(
    RootModel[
        Annotated[
            Annotated[OpenModal, Tag("open")] | Annotated[ClosedModal, Tag("closed")],
            by_flag("open", "open", "closed"),
        ]
    ]
):
    """``geometryModal``."""


# ---------- planning drops (geometryFreeSpot, geometryPlanDrag) ----------


class FreeSpot(Reply):
    """``geometryFreeSpot``: the top-left corner of an empty box in the safe area, out of every snap radius."""

    spot: Point | None
    area: Rect


class Staging(Reply):
    """A free spot to move the block to first, from where the straight path snaps only where wanted
    (``clean``) or at least ends there (a spot whose path only lands, when no spot gives a clean one)."""

    spot: Point
    """Top-left corner of the block there."""
    end: Point
    """Where to release the grab point to put it there."""
    clean: bool = True


class DragPlan(Reply):
    """``geometryPlanDrag``: press and release points for a drag that joins two connections.

    The page replays Blockly's choice of connection along the straight mouse path: ``clean`` when
    no other connection is ever the candidate, ``lands`` when the candidate at the release (and a few
    pixels around it) is the wanted one, other candidates' previews on the way replayed as drawn.
    """

    grab: Point | None
    """None: no point of the block can be pressed in the safe area."""
    end: Point
    rect: Rect
    reference: Point
    """The grab point, or the block's centre when it has none; ``end`` is relative to it."""
    end_visible: bool
    clean: bool
    lands: bool = False
    reason: str | None = None
    """Why the path is not clean."""
    staging: Staging | None = None
