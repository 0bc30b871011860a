"""Where upstream's pre-action clicks land: the editor layout its drag tasks were recorded in.

Upstream recorded every drag task in its scratch-gui fork (5.1.104) at a 1280x720 page after
clicking "Switch to small stage", and selects sprites and palette categories by clicking page
pixels. Nothing in the task files names the layout, so it is deduced from the 60 tasks
themselves; each constant says which data fixes it:

- **Blocks area.** Upstream's pan script adds to the workspace's initial transform; subtracting
  its payload from the recorded ``workspace_state`` gives ``translate(310, ...)`` in 51 of 60
  tasks. 310 is Blockly's ``absoluteLeft``: the category column (60 px) plus the flyout (250 px,
  scratch-blocks' default width). Every flyout task's ``drag_start_point`` has x in 90-167 and
  every canvas task's x is over 400, on either side of that edge.
- **Category column.** The six distinct category clicks (x 31; y 115, 160, 250, 295, 340, 430)
  each select the category of the flyout block the task then drags (motion, looks, events,
  control, sensing, variables), and all six lie on ``y = 92 + 45 * (i + 0.5)`` rounded up, where
  ``i`` is the category's index in Scratch's order: items 45 px tall below a 92 px header (the
  menu bar, 48 px, and the tabs, 44 px).
- **Sprite tiles.** Clicks at (1143, 420) select the 2nd sprite of three projects (Battery, Goal,
  Buildings; upstream's own ``sprite`` field agrees) and clicks at (1071, 492) the 3rd of two
  (Switch, Power Up). In a regular grid that is only possible with 2 columns, 72 px apart both
  ways, the first tile centred at (1071, 420): with 1 column the 2nd sprite would sit on the
  2nd row, with 3 or more the 3rd would sit on the 1st. Tiles are ordered as the project lists
  its sprites (the VM sorts targets back into ``targets`` order when loading).
- **Stage selector.** One click position, (1236, 501), selects the Stage (two tasks whose
  reference block is the Stage's).

A click is mapped only when it falls well inside one of these boxes (``HIT_MARGIN`` px from any
edge of the deduced cell, and only the cells the deduction covers); anything else is reported,
not guessed.
"""

from __future__ import annotations

from dataclasses import dataclass

from workers.contract import DRAG_VIEWPORT, PaletteCategory

PALETTE_CATEGORIES: tuple[PaletteCategory, ...] = (
    "motion",
    "looks",
    "sound",
    "events",
    "control",
    "sensing",
    "operators",
    "variables",
    "myBlocks",
)

UPSTREAM_VIEWPORT = DRAG_VIEWPORT
"""Page size (CSS px) of upstream's browser sessions (and of ours)."""

HIT_MARGIN = 4
"""A click this close to the edge of a deduced cell is not mapped: the cell's exact extent is inferred."""


@dataclass(frozen=True)
class Box:
    """A page rectangle, left/top inclusive, right/bottom exclusive."""

    left: float
    top: float
    right: float
    bottom: float

    def contains(self, x: float, y: float, margin: float = 0) -> bool:
        return self.left + margin <= x < self.right - margin and self.top + margin <= y < self.bottom - margin


HEADER_HEIGHT = 92
"""Menu bar (48 px) plus the Code/Costumes/Sounds tabs (44 px)."""

CATEGORY_COLUMN = Box(0, HEADER_HEIGHT, 60, UPSTREAM_VIEWPORT[1])
CATEGORY_ITEM_HEIGHT = 45

FLYOUT = Box(CATEGORY_COLUMN.right, HEADER_HEIGHT, 310, UPSTREAM_VIEWPORT[1])
"""The palette's blocks; it ends where the workspace's initial translate starts (x 310)."""

SPRITE_TILE_ORIGIN = (1071, 420)
"""Centre of the first sprite tile."""

SPRITE_TILE_PITCH = 72
SPRITE_TILE_SIZE = 64
"""Tiles are 64 px with 8 px between them; only the tile itself is trusted to select its sprite."""

SPRITE_COLUMNS = 2
SPRITE_ROWS = 3
"""Rows below the third are not trusted: the "Choose a Sprite" button floats over the pane's bottom."""

STAGE_SELECTOR = Box(1212, 461, 1260, 541)
"""Around the one observed Stage click (1236, 501): the selector's full extent is not in the data."""


def category_at(x: float, y: float) -> PaletteCategory | None:
    """The category whose button is at (x, y), or None if the point is not clearly on one."""
    if not CATEGORY_COLUMN.contains(x, y):
        return None
    index = int((y - HEADER_HEIGHT) // CATEGORY_ITEM_HEIGHT)
    item = Box(
        CATEGORY_COLUMN.left,
        HEADER_HEIGHT + index * CATEGORY_ITEM_HEIGHT,
        CATEGORY_COLUMN.right,
        HEADER_HEIGHT + (index + 1) * CATEGORY_ITEM_HEIGHT,
    )
    if index >= len(PALETTE_CATEGORIES) or not item.contains(x, y, HIT_MARGIN):
        return None
    return PALETTE_CATEGORIES[index]


def sprite_tile_at(x: float, y: float) -> int | None:
    """The 0-based index of the sprite tile at (x, y) (sprites in project order), or None."""
    x0, y0 = SPRITE_TILE_ORIGIN
    column = round((x - x0) / SPRITE_TILE_PITCH)
    row = round((y - y0) / SPRITE_TILE_PITCH)
    if not (0 <= column < SPRITE_COLUMNS and 0 <= row < SPRITE_ROWS):
        return None
    cx, cy = x0 + column * SPRITE_TILE_PITCH, y0 + row * SPRITE_TILE_PITCH
    half = SPRITE_TILE_SIZE / 2
    if not Box(cx - half, cy - half, cx + half, cy + half).contains(x, y, HIT_MARGIN):
        return None
    return row * SPRITE_COLUMNS + column


def on_stage_selector(x: float, y: float) -> bool:
    return STAGE_SELECTOR.contains(x, y)


def on_flyout(x: float, y: float) -> bool:
    return FLYOUT.contains(x, y)
