"""The single-step drag benchmark's own contract: a task's semantic set-up, the job a worker is given, and what
one attempt did.

A drag job (``DragSpec``) is one observation, one model call and one real drag, so it returns an ordinary
``JobResult`` (one step, one test: "the expected connection was made") carrying a ``DragAttempt`` with the
predicted points and their distances to the exact regions. What the core shares of a drag (the view, page
regions, connection kinds: ``workers.contract``; the setting and how a reply was read: ``workers.agent_api``)
is not here.
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator

from workers.agent_api import DragParse, DragSetting
from workers.contract import AgentJob, ConnectionKind, DragRegions, DragView, JobDetail, ObservationSettings, Point

DragType = Literal["T1", "T2"]
"""T1: stacking (``parent``, ``next``); T2: nesting (``substack_1``, ``substack_2``, ``input``)."""

CONNECTIONS_OF: dict[DragType, tuple[ConnectionKind, ...]] = {
    "T1": ("parent", "next"),
    "T2": ("substack_1", "substack_2", "input"),
}

DRAG_SETTINGS: tuple[DragSetting, ...] = ("baseline", "gt_start", "knowledge")


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


class DragSpec(AgentJob):
    """One drag job as a worker sees it: who answers, under which setting."""

    setting: DragSetting
    element_list: bool = False
    """Show the model primitive mode's element list and accept ``<index>`` answers."""

    observation: ObservationSettings | None = None
    """How the element list is made (None without one)."""


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
