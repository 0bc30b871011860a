"""Who answers a drag task: the ``llm`` agent, and two scripted ones that test the benchmark itself.

- ``oracle`` aims at the deepest pixels of the exact regions: it must pass every task, so a miss
  is a bug in the regions, the view or the verification, never in the agent.
- ``jitter`` is the oracle plus Gaussian noise of ``sigma_px`` on each point (its own stream per
  task and seed): start and end accuracy fall as the noise grows, as the regions' size predicts,
  which tests the metrics.
- ``llm`` asks the job's model once, in its coordinate convention, and parses what it says.

Every agent returns a ``DragAnswer`` in page px; a reply that names no usable drag is an answer
too (its ``parse`` class says why), so nothing is dropped silently.
"""

from __future__ import annotations

import hashlib
import random
from typing import ClassVar

from pydantic import BaseModel, ConfigDict, Field

from workers.agent_api import DragAgentBase, DragAnswer, DragQuestion, ModelSource, build_agent
from workers.agents._coordinates import SCREEN, coordinate_system, model_space
from workers.contract import AgentRef, AgentUnavailableError, ModelSpec, Point
from workers.kinds.drag._prompts import drag_messages
from workers.kinds.drag._reply import parse_drag_reply

__all__ = ["DragAnswer", "DragQuestion", "JitterDragAgent", "LLMDragAgent", "OracleDragAgent", "drag_agent"]


def _aim(question: DragQuestion) -> tuple[Point, Point]:
    regions = question.regions
    if regions is None:
        raise AgentUnavailableError("a scripted drag agent needs the task's regions")
    return regions.fixed_start, regions.end.deepest()


class OracleDragAgent(DragAgentBase):
    """Presses at the fixed start and releases at the end region's deepest pixel."""

    privileged = True

    async def answer(self, question: DragQuestion, model: ModelSpec | None, models: ModelSource) -> DragAnswer:
        start, end = _aim(question)
        return DragAnswer(parse="ok", start=(float(start[0]), float(start[1])), end=(float(end[0]), float(end[1])))


class JitterParams(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)

    sigma_px: float = Field(default=8.0, gt=0, le=200)
    """Standard deviation of the noise on each coordinate of each point, in page px."""


class JitterDragAgent(DragAgentBase):
    """The oracle's points plus independent Gaussian noise, seeded by task and seed."""

    Params: ClassVar[type[BaseModel]] = JitterParams
    privileged = True

    def __init__(self, params: BaseModel | None = None) -> None:
        super().__init__(params)
        self.sigma = float(self.params.sigma_px)  # type: ignore[attr-defined]

    async def answer(self, question: DragQuestion, model: ModelSpec | None, models: ModelSource) -> DragAnswer:
        start, end = _aim(question)
        digest = hashlib.sha256(f"{question.task_id}:{question.seed}".encode()).digest()
        rng = random.Random(int.from_bytes(digest[:8], "big"))
        if question.gt_start is not None:  # the start is given: only the drop is the agent's
            noisy_start = (float(start[0]), float(start[1]))
        else:
            noisy_start = (start[0] + rng.gauss(0, self.sigma), start[1] + rng.gauss(0, self.sigma))
        # The drop keeps the block's grip: the oracle's end moves with the (noisy) press.
        shift = (noisy_start[0] - start[0], noisy_start[1] - start[1])
        noisy_end = (end[0] + shift[0] + rng.gauss(0, self.sigma), end[1] + shift[1] + rng.gauss(0, self.sigma))
        return DragAnswer(parse="ok", start=_rounded(noisy_start), end=_rounded(noisy_end))


class LLMDragAgent(DragAgentBase):
    """One call to the job's model; its reply parsed leniently and mapped from its coordinates to page px."""

    needs_model = True

    async def answer(self, question: DragQuestion, model: ModelSpec | None, models: ModelSource) -> DragAnswer:
        if model is None:
            raise AgentUnavailableError("the llm drag agent needs a model")
        system = coordinate_system(model)
        width, height = model_space(system)
        to_model = (width / SCREEN[0], height / SCREEN[1])
        gt = question.gt_start
        messages = drag_messages(
            question.instruction,
            question.setting,
            question.screenshot_png,
            system,
            gt_start_model=None if gt is None else (round(gt[0] * to_model[0], 1), round(gt[1] * to_model[1], 1)),
            element_text=question.element_text,
        )
        reply = await models.connect(model).complete(messages)
        parsed = parse_drag_reply(reply.text, indices=question.element_centres or None)
        if parsed.parse != "ok" or parsed.start is None or parsed.end is None:
            return DragAnswer(parse=parsed.parse, detail=parsed.detail)

        def page(point: tuple[float, float], in_page: bool) -> tuple[float, float]:
            return point if in_page else (point[0] / to_model[0], point[1] / to_model[1])

        start, end = page(parsed.start, parsed.start_in_page), page(parsed.end, parsed.end_in_page)
        off = [name for name, p in (("start", start), ("end", end)) if not _on_screen(p)]
        if off:
            detail = f"{' and '.join(off)} off the {SCREEN[0]}x{SCREEN[1]} screenshot (in page px)"
            return DragAnswer(parse="out_of_screen", start=start, end=end, detail=detail)
        return DragAnswer(parse="ok", start=start, end=end)


def _on_screen(point: tuple[float, float]) -> bool:
    return 0 <= point[0] < SCREEN[0] and 0 <= point[1] < SCREEN[1]


def _rounded(point: tuple[float, float]) -> tuple[float, float]:
    return round(point[0], 1), round(point[1], 1)


def drag_agent(ref: AgentRef) -> DragAgentBase:
    """The drag agent a job names, found in the drag agents' registry and built with its validated params
    (``AgentUnavailableError`` names the problem)."""
    agent: DragAgentBase = build_agent(ref, "drag")
    return agent
