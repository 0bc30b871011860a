"""The single-step drag benchmark as driver and worker share it: a task's semantic set-up, the job
a worker is given, the exact feasible regions it computes, and what one attempt did.

A drag job (``DragSpec``, next to ``EpisodeSpec``) is one observation, one model call and one real
drag, so it returns an ordinary ``JobResult`` (one step, one test: "the expected connection
was made") carrying a ``DragAttempt`` with the predicted points and their distances to the regions.
"""

from __future__ import annotations

import math
from collections import deque
from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator

from workers.contract._detail import JobDetail

DragType = Literal["T1", "T2"]
"""T1: stacking (``parent``, ``next``); T2: nesting (``substack_1``, ``substack_2``, ``input``)."""

ConnectionKind = Literal["parent", "next", "substack_1", "substack_2", "input"]

CONNECTIONS_OF: dict[DragType, tuple[ConnectionKind, ...]] = {
    "T1": ("parent", "next"),
    "T2": ("substack_1", "substack_2", "input"),
}

DragSetting = Literal["baseline", "gt_start", "knowledge"]
"""``baseline``: screenshot and instruction; ``gt_start``: a feasible start is marked and stated;
``knowledge``: hints about where to grab and where to drop."""

DRAG_SETTINGS: tuple[DragSetting, ...] = ("baseline", "gt_start", "knowledge")

PaletteCategory = Literal[
    "motion", "looks", "sound", "events", "control", "sensing", "operators", "variables", "myBlocks"
]
"""scratch-blocks' category ids (locale-independent), in the order the category column lists them."""

DRAG_VIEWPORT = (1280, 720)
"""Page size (CSS px) of drag observations, upstream's too."""

Point = tuple[int, int]
"""A page position in CSS px."""


class CanvasSource(BaseModel):
    """A block already on the workspace; the stack below it moves with it."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    kind: Literal["canvas"] = "canvas"

    block_id: str = Field(min_length=1)
    """The block the drag starts on (the top of the stack that moves)."""

    opcode: str = Field(min_length=1)

    tail_block_id: str = Field(min_length=1)
    """The last block of the moving stack: for ``parent`` the reference must hang below it."""


class FlyoutSource(BaseModel):
    """A new block dragged out of the palette; it gets its id only once dropped."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    kind: Literal["flyout"] = "flyout"

    opcode: str = Field(min_length=1)
    """The palette block to drag (for ``data_variable``, ``connection.variable_name`` says which one)."""


DragSource = Annotated[CanvasSource | FlyoutSource, Field(discriminator="kind")]


class ExpectedConnection(BaseModel):
    """How the dragged block must end up attached to the reference block (upstream's verification).

    - ``next``: the source hangs directly below the reference.
    - ``parent``: the reference hangs directly below the source stack's tail, and that tail still hangs
      below the source (the whole stack moved; upstream also passes a drag of the tail alone).
    - ``substack_1`` / ``substack_2``: the source is the first block of the reference's
      ``SUBSTACK`` / ``SUBSTACK2``.
    - ``input``: the source fills the reference's input ``input_name``.
    """

    model_config = ConfigDict(frozen=True, extra="forbid")

    kind: ConnectionKind

    input_name: str | None = Field(default=None, min_length=1)
    """The reference's input (``CONDITION``, ``OPERAND1``...); set for ``input`` only."""

    variable_name: str | None = Field(default=None, min_length=1)
    """For ``input`` only: the input must hold the variable reporter of this name (upstream's optional check)."""

    @model_validator(mode="after")
    def _input_fields(self) -> ExpectedConnection:
        if self.kind == "input" and self.input_name is None:
            raise ValueError("an 'input' connection needs input_name")
        if self.kind != "input" and (self.input_name is not None or self.variable_name is not None):
            raise ValueError(f"input_name and variable_name are for 'input' connections, not {self.kind!r}")
        return self


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


class DragPayload(BaseModel):
    """A drag task's content, shipped once per task to the object store and shared by its jobs."""

    model_config = ConfigDict(frozen=True)

    task_id: str
    type: DragType
    instruction: str
    initial_project: bytes
    source: DragSource
    reference_block_id: str
    reference_opcode: str
    connection: ExpectedConnection
    view: DragView


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


DragParse = Literal["ok", "no_answer", "unparsed", "bad_index", "out_of_screen"]
"""How the model's reply was read: two points (``ok``), an empty reply, no drag found, an element
index the list does not have, or a point off the screenshot."""


class DragAttempt(JobDetail):
    """What one drag job did, in page px; the distances are to the task's exact regions."""

    kind: Literal["drag"] = "drag"

    setting: DragSetting
    parse: DragParse
    start: tuple[float, float] | None = None
    """The press position as performed (None when the reply gave none)."""

    end: tuple[float, float] | None = None
    start_in_region: bool | None = None
    start_error_px: float | None = None
    """Distance from ``start`` to the start region (0 inside)."""

    end_in_region: bool | None = None
    """Whether the release, translated by ``fixed_start - start``, lies in the end region."""

    end_error_px: float | None = None
    connected: bool = False
    """The verification from the VM's block structure: the expected connection, exactly."""

    observed: str = ""
    """What the verification found, in words (for people reading a failure)."""

    gt_start: Point | None = None
    """The start marked on the screenshot under ``gt_start``."""

    regions: DragRegions
    """The task's exact regions the distances were measured against, kept with the attempt."""

    regions_s: float = 0.0
    """Time the worker spent computing the regions (0 when they came from its cache)."""

    annotated_sha256: str | None = None
    """The annotated screenshot (regions and drag drawn on), among ``JobResult.images``."""
