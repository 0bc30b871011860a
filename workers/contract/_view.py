"""The editor page as the single-step benchmarks frame it: a view set up in the editor's own terms, page points and
pixel regions, and how one block attaches to another.

Shared by the drag kind (its tasks' views, its exact regions), the perception items framed like drag tasks, the
driver's editing core (framing a view, detaching blocks) and the agent API (a drag's exact regions, which
privileged drag agents are shown).
"""

from __future__ import annotations

import math
from collections import deque
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator

ConnectionKind = Literal["parent", "next", "substack_1", "substack_2", "input"]
"""How one block is attached to another (see ``ExpectedConnection`` in ``workers.kinds.drag``)."""

PaletteCategory = Literal[
    "motion", "looks", "sound", "events", "control", "sensing", "operators", "variables", "myBlocks"
]
"""scratch-blocks' category ids (locale-independent), in the order the category column lists them."""

DRAG_VIEWPORT = (1280, 720)
"""Page size (CSS px) of drag observations, upstream's too."""

Point = tuple[int, int]
"""A page position in CSS px."""


class DragView(BaseModel):
    """The editor state set up before the screenshot, in the editor's own terms."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    sprite: str | None
    """The sprite whose scripts are shown, by its exact name; None when the Stage is selected."""

    category: PaletteCategory | None = None
    """The palette category selected (its blocks are at the top of the flyout); None leaves the
    palette as the editor opens it (only for sources on the canvas)."""

    flyout_scroll: float = 0
    """Flyout pixels scrolled down past the top of ``category`` (the mouse wheel's deltaY)."""

    scroll_x: float
    """Workspace x (units) at the left edge of the Blockly SVG, which spans the category column and
    flyout too: a block at workspace x appears at ``svg_left + (x - scroll_x) * scale``."""

    scroll_y: float
    """Workspace y (units) at the top edge of the Blockly SVG."""

    scale: float = Field(gt=0)
    """Workspace zoom (Scratch opens at 0.675)."""

    stage_size: Literal["small", "large"] = "small"
    """Stage size mode; the small stage widens the workspace."""

    viewport: tuple[int, int] = Field(default=DRAG_VIEWPORT)
    """Page size in CSS px."""

    @model_validator(mode="after")
    def _scroll_needs_category(self) -> DragView:
        if self.flyout_scroll and self.category is None:
            raise ValueError("flyout_scroll is relative to a category: set category too")
        return self


class Region(BaseModel):
    """A set of page pixels as run-length rows ``(y, x_first, x_last)``, inclusive, sorted by y then x."""

    model_config = ConfigDict(frozen=True)

    rows: tuple[tuple[int, int, int], ...] = ()

    @property
    def area(self) -> int:
        return sum(x1 - x0 + 1 for _, x0, x1 in self.rows)

    @property
    def empty(self) -> bool:
        return not self.rows

    def contains(self, x: float, y: float) -> bool:
        """Whether the pixel that holds (x, y) is in the region (positions round to the nearest pixel)."""
        px, py = round(x), round(y)
        return any(row_y == py and x0 <= px <= x1 for row_y, x0, x1 in self.rows)

    def distance(self, x: float, y: float) -> float:
        """Euclidean distance in px to the nearest pixel of the region (0 inside; inf when empty)."""
        best = math.inf
        for row_y, x0, x1 in self.rows:
            dy = row_y - y
            if dy * dy >= best * best:
                continue
            dx = x0 - x if x < x0 else x - x1 if x > x1 else 0.0
            best = min(best, math.hypot(dx, dy))
        return best

    def deepest(self) -> Point:
        """The pixel farthest from the region's outside (4-neighbour steps), nearest to its centre of mass
        among equals: where an aim has the most room for error."""
        if self.empty:
            raise ValueError("an empty region has no point")
        inside = set(self.points())
        depth: dict[Point, int] = {}
        frontier = deque()
        for x, y in inside:
            if any(n not in inside for n in ((x + 1, y), (x - 1, y), (x, y + 1), (x, y - 1))):
                depth[(x, y)] = 0
                frontier.append((x, y))
        while frontier:
            x, y = frontier.popleft()
            for n in ((x + 1, y), (x - 1, y), (x, y + 1), (x, y - 1)):
                if n in inside and n not in depth:
                    depth[n] = depth[(x, y)] + 1
                    frontier.append(n)
        cx = sum(x for x, _ in inside) / len(inside)
        cy = sum(y for _, y in inside) / len(inside)
        return min(inside, key=lambda p: (-depth[p], math.hypot(p[0] - cx, p[1] - cy), p))

    def points(self) -> list[Point]:
        return [(x, y) for y, x0, x1 in self.rows for x in range(x0, x1 + 1)]

    def boundary(self) -> tuple[list[Point], list[Point]]:
        """Its pixels with an outside 4-neighbour, and those outside pixels: where a region is checked first."""
        inside = set(self.points())
        rim, around = set(), set()
        for x, y in inside:
            for n in ((x + 1, y), (x - 1, y), (x, y + 1), (x, y - 1)):
                if n not in inside:
                    rim.add((x, y))
                    around.add(n)
        return sorted(rim), sorted(around)


class DragRegions(BaseModel):
    """A task's exact feasible regions in page px at its view, as the worker's editor computed them."""

    model_config = ConfigDict(frozen=True)

    start: Region
    """Every press position that grabs the source (and so drags it, or its stack)."""

    fixed_start: Point
    """The start the end region is computed for (a deep pixel of ``start``)."""

    end: Region
    """Every release position that, for a press at ``fixed_start``, makes exactly the expected connection."""

    computed_s: float = 0.0
