"""Primitive episodes through the runner: observations reach the agent, gestures act, OCR degrades loudly."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
import pytest

from scratchworld_dist.kinds.tasks import EpisodeMatrix, TaskContent, plan_jobs, read_task
from scratchworld_dist.suites import load_suite
from scratchworld_dist.sweep import worker_job
from tests.conftest import SUITE_DIR
from workers.agent_api import AgentBase, StepResult
from workers.contract import (
    Action,
    CompositeAction,
    CompositeObservation,
    Done,
    Mode,
    Observation,
    ObservationSettings,
    PrimitiveAction,
    PrimitiveObservation,
)
from workers.kinds.tasks import EpisodeRunner, EpisodeSpec

pytestmark = pytest.mark.browser


@pytest.fixture(scope="module")
def content() -> TaskContent:
    return read_task(load_suite(SUITE_DIR).task("quiz_score"))


def episode(content: TaskContent, mode: Mode, observation: ObservationSettings | None = None) -> EpisodeSpec:
    (job,) = plan_jobs(
        EpisodeMatrix(
            models=[None], modes=[mode], agent="noop", tasks=[content], seeds=[0], max_steps=10, observation=observation
        )
    )
    return worker_job(job, 1, 120)


class ClickByText(AgentBase):
    """Observes, clicks the element with a given text by its index, then checks what changed."""

    observes = True

    def __init__(self, kind: str, text: str) -> None:
        super().__init__()
        self.kind, self.text = kind, text
        self.seen: list[PrimitiveObservation] = []

    async def act(self, observation: Observation | None, last: StepResult | None) -> Action:
        assert isinstance(observation, PrimitiveObservation)
        self.seen.append(observation)
        if len(self.seen) == 1:
            index = next(e.index for e in observation.elements if e.type == self.kind and e.text == self.text)
            return PrimitiveAction(api="click", args={"index": index})
        return Done()


async def test_an_observing_agent_sees_the_page_and_acts_by_index(
    episode_runner: EpisodeRunner, content: TaskContent
) -> None:
    agent = ClickByText("category_menu_item", "Variables")
    result = await episode_runner.run(episode(content, "primitive"), content.payload, agent)
    assert result.outcome == "failed"  # nothing was built; the episode itself ran cleanly
    first, second = agent.seen
    image = cv2.imdecode(np.frombuffer(first.screenshot_png, np.uint8), cv2.IMREAD_COLOR)
    assert image.shape == (720, 1280, 3)
    assert first.settled
    assert first.text.splitlines()[0].startswith("0  ")
    assert any(e.type == "stage" for e in first.elements)
    # The click opened the Variables category: the palette now offers to make a variable.
    assert not any(e.type == "flyout_buttons" and "Variable" in e.text for e in first.elements)
    assert any(e.type == "flyout_buttons" and e.text == "Make a Variable" for e in second.elements)
    click, done = result.steps
    assert (click.action, click.ok, done.action) == ("click", True, "done")
    assert click.observation_s > 0
    assert click.latency_s >= click.observation_s
    assert click.warnings == []
    # The trajectory keeps what was shown: the screenshot by digest among the images, and the list.
    assert click.observation is not None and done.observation is not None
    assert click.observation.text is None
    assert result.images[click.observation.screenshot or ""] == first.screenshot_png
    assert click.observation.elements == first.elements
    assert done.observation.elements == second.elements


async def test_a_broken_ocr_backend_degrades_to_a_dom_list_with_a_warning(
    episode_runner: EpisodeRunner, content: TaskContent, tmp_path: Path
) -> None:
    empty = tmp_path / "no-model"
    empty.mkdir()
    settings = ObservationSettings(ocr="paddleocr", paddle_det_model_dir=empty, paddle_rec_model_dir=empty)
    agent = ClickByText("category_menu_item", "Looks")
    result = await episode_runner.run(episode(content, "primitive", settings), content.payload, agent)
    assert result.outcome == "failed"
    assert all(step.ok for step in result.steps)
    for step in result.steps:
        (warning,) = step.warnings
        assert "OCR failed, the element list is DOM-only" in warning
        assert "inference.yml" in warning
    assert all(e.source == "dom" for e in agent.seen[0].elements)
    assert any(e.type == "blocks" for e in agent.seen[0].elements)


class OtherModesAction(AgentBase):
    """Sends one action of the other mode, then stops."""

    observes = True

    def __init__(self, action: Action) -> None:
        super().__init__()
        self.plan: list[Action] = [action, Done()]
        self.seen: list[object] = []

    async def act(self, observation: Observation | None, last: StepResult | None) -> Action:
        self.seen.append(observation)
        return self.plan.pop(0)


@pytest.mark.parametrize(
    ("mode", "action", "observation_type"),
    [
        ("primitive", CompositeAction(api="add_block", args={"blockType": "motion_movesteps"}), PrimitiveObservation),
        ("composite", PrimitiveAction(api="click", args={"x": 10, "y": 10}), CompositeObservation),
    ],
)
async def test_actions_of_the_other_mode_are_refused(
    episode_runner: EpisodeRunner, content: TaskContent, mode: Mode, action: Action, observation_type: type
) -> None:
    agent = OtherModesAction(action)
    spec = episode(content, mode, ObservationSettings(ocr="none"))
    result = await episode_runner.run(spec, content.payload, agent)
    refused = result.steps[0]
    assert (refused.ok, refused.error_code) == (False, "UNKNOWN_API")
    assert f"not an action of {mode} mode" in (refused.error_message or "")
    assert isinstance(agent.seen[0], observation_type)
