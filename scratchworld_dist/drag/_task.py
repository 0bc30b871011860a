"""A single-step drag task: which block to drag, where it must connect, and the view it starts in.

Everything here is semantic (block ids, opcodes, a sprite name, a palette category, workspace
scroll and scale), so a task survives a change of viewport, stage size or editor version that
would move every pixel. Upstream's pixel data is kept apart, in ``UpstreamDragReference``,
for cross-checks only.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

from scratchworld_dist.drag._layout import UPSTREAM_VIEWPORT, PaletteCategory
from scratchworld_dist.suites._task import task_id_problem

DragType = Literal["T1", "T2"]
"""T1: stacking (``parent``, ``next``); T2: nesting (``substack_1``, ``substack_2``, ``input``)."""

ConnectionKind = Literal["parent", "next", "substack_1", "substack_2", "input"]

CONNECTIONS_OF: dict[DragType, tuple[ConnectionKind, ...]] = {
    "T1": ("parent", "next"),
    "T2": ("substack_1", "substack_2", "input"),
}

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
    - ``parent``: the reference hangs directly below the source stack's tail.
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

    viewport: tuple[int, int] = Field(default=UPSTREAM_VIEWPORT)
    """Page size in CSS px."""

    @model_validator(mode="after")
    def _scroll_needs_category(self) -> DragView:
        if self.flyout_scroll and self.category is None:
            raise ValueError("flyout_scroll is relative to a category: set category too")
        return self


class UpstreamAction(BaseModel):
    """One of upstream's pre-actions as its task file wrote it (``click``, ``scroll``, ``custom_js``)."""

    model_config = ConfigDict(frozen=True)

    api: str
    args: dict[str, Any] = Field(default_factory=dict)


class UpstreamDragReference(BaseModel):
    """Upstream's pixel data for the task: valid only in upstream's editor (1280x720, small stage,
    after its pre-actions) and kept to cross-check our own geometry. Never used to run a task."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    pre_actions: tuple[UpstreamAction, ...] = ()
    """``switch_sprite_actions`` then ``locate_target_actions``: the clicks the view was derived from."""

    drag_start_point: Point
    """The start upstream dragged from when it computed ``feasible_points``."""

    feasible_start_points: tuple[Point, ...] = ()
    """Starts that pick up the source, sampled on a grid of ``start_grid_step``."""

    feasible_points: tuple[Point, ...] = ()
    """Ends that make the connection for a drag from ``drag_start_point``."""

    start_grid_step: int | None = None
    """The spacing of ``feasible_start_points`` (the gcd of their offsets), None for one point."""

    end_grid_step: int | None = None
    """The spacing of ``feasible_points``; upstream's input tasks sampled ends on one row, 2 px apart."""

    seed_point: Point | None = None
    """Where upstream's search for feasible ends started."""

    first_valid_point: Point | None = None
    """The first feasible end that search found."""


class DragTask(BaseModel):
    """One single-step drag: the model sees ``instruction`` and a screenshot of ``view``."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    id: str
    type: DragType
    instruction: str = Field(min_length=1)
    """What the model is told."""

    description: str = ""
    """A note for people reading results; never shown to the model."""

    initial_project: Path
    """The .sb3 loaded before the view is set up."""

    source: DragSource
    reference_block_id: str = Field(min_length=1)
    """The block already on the workspace that the source must connect to."""

    reference_opcode: str = Field(min_length=1)
    connection: ExpectedConnection

    view: DragView | None
    """None only for an upstream task whose pre-actions could not be mapped (see the suite's problems)."""

    upstream: UpstreamDragReference | None = None

    @field_validator("id")
    @classmethod
    def _plain_id(cls, value: str) -> str:
        problem = task_id_problem(value)
        if problem is not None:
            raise ValueError(problem)
        return value

    @model_validator(mode="after")
    def _consistent(self) -> DragTask:
        if self.connection.kind not in CONNECTIONS_OF[self.type]:
            allowed = ", ".join(CONNECTIONS_OF[self.type])
            raise ValueError(f"a {self.type} task connects by {allowed}, not {self.connection.kind!r}")
        if self.view is not None and isinstance(self.source, FlyoutSource) and self.view.category is None:
            raise ValueError("a source from the flyout needs view.category")
        return self

    def dump(self, initial_project: str) -> str:
        """The task as a file of our drag-suite format, its project named relative to the suite root."""
        data = self.model_dump(mode="json")
        data["initial_project"] = initial_project
        return json.dumps(data, indent=2, ensure_ascii=False) + "\n"
