"""A perception item: one question about one screenshot, its answer, and (for items we generate) why.

Upstream's 200 items carry only a question and a label written by a model. Items we generate also
name the view their screenshot was taken of (a saved project and a semantic editor view) and the
``fact`` their answer was derived from, in the VM's own terms (block ids, input names), so the
validity check can open the same view again and re-derive every answer.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator

from scratchworld_dist.suites import task_id_problem
from workers.agent_api import AnswerFormat, ValueKind
from workers.contract import DragView
from workers.kinds.perception import PerceptionPayload, QuestionKind, answer_problem

Position = Literal["topmost", "bottommost", "leftmost", "rightmost"]
"""How a question singles out one of several visible blocks of the same kind."""


class BlockReference(BaseModel):
    """A block as a question names it: its kind's visible name, with a position only when the kind is not
    unique among the visible blocks (``the topmost `say` block``)."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    block: str = Field(min_length=1)
    """The block's id in the view's project."""

    name: str = Field(min_length=1)
    """The kind's visible name as the question writes it, e.g. ``move steps`` or ``set [variable] to``."""

    position: Position | None = None


class ConnectionFact(BaseModel):
    """Is ``subject`` attached where the question says: to the block right above it (``above``), to a block
    right below it (``below``), or in the input ``slot`` of ``parent`` (``slot``)."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    kind: Literal["connection"] = "connection"
    relation: Literal["above", "below", "slot"]
    subject: BlockReference
    parent: BlockReference | None = None
    slot: str | None = None
    """The parent's input name (``SUBSTACK``, ``SUBSTACK2``, ``CONDITION``, ``NUM1``...), for ``slot``."""

    @model_validator(mode="after")
    def _slot_fields(self) -> ConnectionFact:
        if (self.relation == "slot") != (self.parent is not None and self.slot is not None):
            raise ValueError("parent and slot are given exactly for the 'slot' relation")
        return self


class ExistenceFact(BaseModel):
    """Is any block of ``opcodes`` (a kind) or of ``category`` visible in the view."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    kind: Literal["existence"] = "existence"
    name: str = Field(min_length=1)
    """What the question asks about: a kind's visible name, or a category (``motion``)."""

    opcodes: tuple[str, ...] = ()
    """The opcodes answering to ``name`` (several kinds can share a visible name); empty for a category."""

    category: str | None = None

    @model_validator(mode="after")
    def _one_target(self) -> ExistenceFact:
        if bool(self.opcodes) == (self.category is not None):
            raise ValueError("an existence fact names opcodes or a category, not both")
        return self


class FieldFact(BaseModel):
    """What the field (or the value input) ``name`` of ``subject`` shows; for a YES/NO item, whether it
    shows ``asked``."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    kind: Literal["field"] = "field"
    subject: BlockReference
    name: str = Field(min_length=1)
    """A field of the block (``VARIABLE``, ``KEY_OPTION``) or an input whose shadow holds the value (``STEPS``)."""

    asked: str | None = None


Fact = Annotated[ConnectionFact | ExistenceFact | FieldFact, Field(discriminator="kind")]


class UpstreamItemInfo(BaseModel):
    """Where an upstream item came from (kept for cross-reference, never shown to a model)."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    task_id: str
    focus_hint: str | None = None


class PerceptionView(BaseModel):
    """One screenshot we made: a project (as saved, perturbations included) shown in an editor view."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    id: str
    project: Path
    """The saved project, relative to the suite folder (absolute once loaded)."""

    view: DragView
    """The editing target, workspace scroll and zoom, palette and stage size the screenshot shows."""

    screenshot: Path
    source: str = ""
    """The project it was made from (a file name), for people reading the suite."""

    change: str = ""
    """What was changed in that project before the screenshot (a script moved, a block pulled off), in words."""


class PerceptionItem(BaseModel):
    """One question about one screenshot, and its answer."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    id: str
    kind: QuestionKind
    tag: str = Field(min_length=1, max_length=80)
    question: str = Field(min_length=1, max_length=2000)
    answer_format: AnswerFormat
    value_kind: ValueKind | None = None
    answer: str = Field(min_length=1, max_length=500)
    screenshot: Path
    """The screenshot, relative to the suite folder in files (absolute once loaded)."""

    view: str | None = None
    """The ``PerceptionView`` the screenshot is of (generated items)."""

    fact: Fact | None = None
    """What the answer was derived from (generated items)."""

    upstream: UpstreamItemInfo | None = None

    @model_validator(mode="after")
    def _consistent(self) -> PerceptionItem:
        problem = task_id_problem(self.id)
        if problem is not None:
            raise ValueError(problem)
        problem = answer_problem(self.answer_format, self.value_kind, self.answer)
        if problem is not None:
            raise ValueError(problem)
        if self.fact is not None and self.fact.kind != self.kind:
            raise ValueError(f"a {self.kind} item cannot rest on a {self.fact.kind} fact")
        return self

    def payload(self, screenshot_png: bytes) -> PerceptionPayload:
        """What a worker gets: the item with its screenshot's bytes."""
        return PerceptionPayload(
            item_id=self.id,
            kind=self.kind,
            tag=self.tag,
            question=self.question,
            answer_format=self.answer_format,
            value_kind=self.value_kind,
            answer=self.answer,
            screenshot_png=screenshot_png,
        )
