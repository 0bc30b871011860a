"""The agents of the single-step benchmarks (drag and perception): one question, one answer.

An episode agent acts step by step in a live editor; a drag or perception agent is asked once: it gets a
question and answers it, calling the job's model through ``models.connect(model)`` if it needs one (the
same client as episodes: retries, rate limits, costs, the model cache). Each class says which benchmark
it serves (``kinds``) and is registered like episode agents (see ``workers.agent_api._registry``). The words the
questions and answers are made of (a drag's setting, how its reply was read, a perception item's answer format)
are defined here, where agents meet them; the kinds' own models use them too.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar, Literal, Protocol

from pydantic import BaseModel, ConfigDict

from workers.agent_api._agent import NoParams
from workers.agent_api._context import ModelHandle
from workers.contract import DragRegions, ModelSpec, Point

DragSetting = Literal["baseline", "gt_start", "knowledge"]
"""``baseline``: screenshot and instruction; ``gt_start``: a feasible start is marked and stated;
``knowledge``: hints about where to grab and where to drop."""

DragParse = Literal["ok", "no_answer", "unparsed", "bad_index", "out_of_screen"]
"""How the model's reply was read: two points (``ok``), an empty reply, no drag found, an element
index the list does not have, or a point off the screenshot."""

AnswerFormat = Literal["yes_no", "value"]
"""``yes_no``: the answer is YES or NO; ``value``: the exact text a field shows."""

ValueKind = Literal["number", "text", "dropdown"]
"""What a ``value`` answer is: a number (compared as a number when normalized), free text, or a dropdown's
option (compared case-insensitively when normalized)."""


class ModelSource(Protocol):
    """What a single-step agent calls models through: ``connect(spec)`` gives the model's handle."""

    def connect(self, spec: ModelSpec) -> ModelHandle: ...


@dataclass(frozen=True)
class DragQuestion:
    """What a drag agent is shown (``regions`` only reaches privileged agents: the harness's own)."""

    task_id: str
    instruction: str
    setting: DragSetting
    screenshot_png: bytes
    seed: int
    gt_start: Point | None
    """The marked start under ``gt_start`` (page px)."""

    element_text: str | None = None
    element_centres: dict[int, tuple[float, float]] = field(default_factory=dict)
    regions: DragRegions | None = None


class DragAnswer(BaseModel):
    """One drag in page px, or why there is none."""

    model_config = ConfigDict(frozen=True)

    parse: DragParse
    start: tuple[float, float] | None = None
    end: tuple[float, float] | None = None
    detail: str = ""


@dataclass(frozen=True)
class PerceptionQuestion:
    """What a perception agent is asked (``label`` only reaches privileged agents: the harness's own)."""

    item_id: str
    question: str
    answer_format: AnswerFormat
    value_kind: ValueKind | None
    screenshot_png: bytes
    label: str | None = None


class SingleStepAgent:
    """Defaults of a drag or perception agent: no parameters, no model, not privileged; keeps its params."""

    kinds: ClassVar[tuple[str, ...]] = ()
    Params: ClassVar[type[BaseModel]] = NoParams
    needs_model: ClassVar[bool] = False
    privileged: ClassVar[bool] = False
    """Whether it is shown the answer (a drag's regions, an item's label): the harness's own scripted agents only."""

    def __init__(self, params: BaseModel | None = None) -> None:
        self.params = params if params is not None else self.Params()


class DragAgentBase(SingleStepAgent):
    """A drag agent: ``answer`` says where to press and where to release, in page px."""

    kinds: ClassVar[tuple[str, ...]] = ("drag",)

    async def answer(self, question: DragQuestion, model: ModelSpec | None, models: ModelSource) -> DragAnswer:
        raise NotImplementedError


class PerceptionAgentBase(SingleStepAgent):
    """A perception agent: ``answer`` is its reply, scored as a model's would be."""

    kinds: ClassVar[tuple[str, ...]] = ("perception",)

    async def answer(self, question: PerceptionQuestion, model: ModelSpec | None, models: ModelSource) -> str:
        raise NotImplementedError
