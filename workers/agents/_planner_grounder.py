"""The ``planner_grounder`` agent (Agent-S2 style, primitive mode): one model plans, another points.

The planner (the job's model) sees the screenshot and the element list and answers with one
action whose targets are an element's ``index`` or a description in words ("the 'move 10
steps' block in the palette"). Each description goes to the grounding model (``params.grounder``,
e.g. UI-TARS behind an OpenAI-compatible URL) with the screenshot; it answers with one point in
its own coordinate convention, which is mapped to page pixels before the gesture runs. The
job's model is the pair (reports name it ``planner+grounder``), and both models' calls are
retried, rate-limited and costed by the harness.
"""

from __future__ import annotations

import base64
import re
from typing import Any, ClassVar

from pydantic import BaseModel, ConfigDict, JsonValue

from workers.agent_api import ModelHandle, TaskContext
from workers.agents._coordinates import coordinate_system, to_page
from workers.agents._llm_agent import LLMAgent
from workers.agents._prompts import system_prompt
from workers.contract import Action, InvalidReply, Mode, ModelSpec, Observation, PrimitiveObservation, primitive_action

PLANNER_ACTIONS = """\
Actions. Say what to act on; a grounding model finds it on the screenshot. A target is one of: "index" (an \
element of the list), or "description" (the thing to point at, in words precise enough for someone who sees only \
the screenshot, e.g. "the 'move (10) steps' block in the block palette"); a drag has a source and a target, each \
an index or a description.
- click {"index" | "description", "button"?: "left" | "right" | "middle"}
- double_click {"index" | "description"}
- drag_and_drop {"start_index" | "source_description", "end_index" | "target_description", "duration"?: seconds}:
  a block snaps when its top-left corner is dropped near a connection point, so describe where that corner goes.
- scroll {"direction": "up" | "down" | "left" | "right", "amount"?: pixels, "index" | "description"}
- type {"text": str}: type into the focused field.
- key {"key": str}: press one key (Enter, Escape, Backspace, ...). hotkey {"keys": [str, ...]}
- done {}: the task is complete. failed {}: give up."""

GROUNDING_QUERY = "Query: {description}\nOutput only the coordinate of one point in your response."

_DESCRIPTIONS = (
    ("description", "x", "y"),
    ("source_description", "start_x", "start_y"),
    ("target_description", "end_x", "end_y"),
)
_NUMBER = re.compile(r"-?\d+(?:\.\d+)?")


class PlannerGrounderParams(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)

    grounder: ModelSpec
    """The grounding model; its ``coordinates`` (default: by its name, UI-TARS smart-resize) say how it answers."""

    def extra_models(self) -> list[ModelSpec]:
        return [self.grounder]


class GroundingError(Exception):
    """The grounding model's answer holds no point."""


class PlannerGrounderAgent(LLMAgent):
    """The llm agent's conversation for the planner, with descriptions grounded by a second model."""

    Params: ClassVar[type[BaseModel]] = PlannerGrounderParams
    modes: ClassVar[tuple[Mode, ...]] = ("primitive",)

    async def start(self, context: TaskContext) -> None:
        await super().start(context)
        assert isinstance(self.params, PlannerGrounderParams)
        self.grounder: ModelHandle = context.model(self.params.grounder)

    async def system_text(self, context: TaskContext, workflows: str = "") -> str:
        return system_prompt(
            "primitive",
            context.instruction,
            coordinates=None,  # the planner names targets; the grounder writes the positions
            element_list=self.settings.element_list,
            workflows=workflows,
            primitive_actions=PLANNER_ACTIONS,
        )

    async def to_action(self, api: str, args: dict[str, JsonValue], observation: Observation | None) -> Action:
        grounded = dict(args)
        for key, x_key, y_key in _DESCRIPTIONS:
            description = grounded.pop(key, None)
            if description is None:
                continue
            if not isinstance(description, str) or not description.strip():
                return InvalidReply(reason="invalid_args", message=f"{key} must be a non-empty string")
            if not isinstance(observation, PrimitiveObservation):
                return InvalidReply(reason="invalid_args", message="nothing to ground a description on")
            try:
                grounded[x_key], grounded[y_key] = await self.ground(description, observation)
            except GroundingError as error:
                return InvalidReply(reason="grounding_failed", message=str(error))
        return primitive_action({"api": api, "args": grounded})

    async def ground(self, description: str, observation: PrimitiveObservation) -> tuple[float, float]:
        """The page position of what ``description`` names, as the grounding model finds it."""
        url = "data:image/png;base64," + base64.b64encode(observation.screenshot_png).decode()
        messages: list[dict[str, Any]] = [
            {"role": "system", "content": "You are a helpful assistant."},
            {
                "role": "user",
                "content": [
                    {"type": "image_url", "image_url": {"url": url}},
                    {"type": "text", "text": GROUNDING_QUERY.format(description=description)},
                ],
            },
        ]
        answer = (await self.grounder.complete(messages)).text
        numbers = _NUMBER.findall(answer)
        if len(numbers) < 2:
            raise GroundingError(f"the grounding model gave no point for {description!r}: {answer[:200]!r}")
        point = to_page({"x": float(numbers[0]), "y": float(numbers[1])}, coordinate_system(self.grounder.spec))
        return float(point["x"]), float(point["y"])  # type: ignore[arg-type]
