"""A single-step drag task: which block to drag, where it must connect, and the view it starts in.

Everything here is semantic (block ids, opcodes, a sprite name, a palette category, workspace
scroll and scale), so a task survives a change of viewport, stage size or editor version that
would move every pixel; its parts are the worker contract's models, shipped to a worker as a
``DragPayload``. Upstream's pixel data is kept apart, in ``UpstreamDragReference``,
for cross-checks only.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

from scratchworld_dist.suites import task_id_problem
from workers.contract import DragView, Point
from workers.kinds.drag import CONNECTIONS_OF, DragPayload, DragSource, DragType, ExpectedConnection, FlyoutSource


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

    def payload(self, initial_project: bytes) -> DragPayload:
        """What a worker needs to run the task (a task without a view cannot be run)."""
        if self.view is None:
            raise ValueError(f"drag task {self.id} has no view")
        return DragPayload(
            task_id=self.id,
            type=self.type,
            instruction=self.instruction,
            initial_project=initial_project,
            source=self.source,
            reference_block_id=self.reference_block_id,
            reference_opcode=self.reference_opcode,
            connection=self.connection,
            view=self.view,
        )

    def dump(self, initial_project: str) -> str:
        """The task as a file of our drag-suite format, its project named relative to the suite root."""
        data = self.model_dump(mode="json")
        data["initial_project"] = initial_project
        return json.dumps(data, indent=2, ensure_ascii=False) + "\n"
