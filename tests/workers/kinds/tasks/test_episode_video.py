"""Episode video: recording the agent's editor adds no step and no page time, and changes nothing an agent sees
or a verdict judges; the video covers the episode on the wall clock its steps were timed on."""

from __future__ import annotations

import hashlib
import io
import json
import zipfile

import av
import pytest

from scratchworld_dist.kinds.tasks import EpisodeMatrix, TaskContent, plan_jobs, read_task
from scratchworld_dist.suites import load_suite
from scratchworld_dist.sweep import worker_job
from tests.conftest import SUITE_DIR
from workers.agent_api import AgentBase, StepResult
from workers.contract import (
    Action,
    Done,
    EpisodeClock,
    JobResult,
    Observation,
    ObservationSettings,
    PrimitiveAction,
    PrimitiveObservation,
    RecordSettings,
)
from workers.kinds.tasks import EpisodeRunner, EpisodeSpec

pytestmark = pytest.mark.browser


@pytest.fixture(scope="module")
def content() -> TaskContent:
    # A ball that travels across the stage once its script runs: the stage changes at every step.
    return read_task(load_suite(SUITE_DIR).task("bounce_speedup"))


def episode(content: TaskContent, record: RecordSettings) -> EpisodeSpec:
    (job,) = plan_jobs(
        EpisodeMatrix(
            models=[None],
            modes=["primitive"],
            agent="noop",
            tasks=[content],
            seeds=[3],
            max_steps=8,
            observation=ObservationSettings(ocr="none"),
            episode_clock=EpisodeClock(mode="virtual", settle_ms=300),
            record=record,
        )
    )
    return worker_job(job, 1, 300)  # type: ignore[return-value]


class RunTheScriptAndDrag(AgentBase):
    """Clicks the green-flag script (the ball starts moving), drags a palette block onto the canvas, types into
    nothing in particular, then says done; keeps every screenshot it was shown."""

    observes = True

    def __init__(self) -> None:
        super().__init__()
        self.seen: list[str] = []

    async def act(self, observation: Observation | None, last: StepResult | None) -> Action:
        assert isinstance(observation, PrimitiveObservation)
        self.seen.append(hashlib.sha256(observation.screenshot_png).hexdigest())
        turn = len(self.seen)
        if turn == 1:
            script = next(e for e in observation.elements if e.type == "blocks" and "event_whenflagclicked" in e.text)
            return PrimitiveAction(api="click", args={"index": script.index})
        if turn == 2:
            block = next(e for e in observation.elements if e.type == "blocks" and "on canvas" not in e.text)
            return PrimitiveAction(api="drag_and_drop", args={"start_index": block.index, "end_x": 700, "end_y": 500})
        if turn == 3:
            return PrimitiveAction(api="type", args={"text": "hi"})
        return Done()


def blocks_of(result: JobResult) -> list[list[str]]:
    """Each target's blocks (opcode, its parent's opcode, fields, where a top block sits), without their ids:
    Blockly names a new block at random, recorded or not."""
    assert result.final_project is not None
    with zipfile.ZipFile(io.BytesIO(result.final_project)) as archive:
        project = json.loads(archive.read("project.json"))
    found = []
    for target in project["targets"]:
        blocks = {key: block for key, block in target["blocks"].items() if isinstance(block, dict)}
        found.append(
            sorted(
                json.dumps(
                    [
                        block["opcode"],
                        blocks[block["parent"]]["opcode"] if block.get("parent") in blocks else None,
                        block["fields"],
                        block.get("x"),
                        block.get("y"),
                    ],
                    sort_keys=True,
                )
                for block in blocks.values()
            )
        )
    return found


async def run(runner: EpisodeRunner, content: TaskContent, record: RecordSettings) -> tuple[JobResult, list[str]]:
    agent = RunTheScriptAndDrag()
    result = await runner.run(episode(content, record), content.payload, agent)
    assert [step.action for step in result.steps] == ["click", "drag_and_drop", "type", "done"], result.error_message
    return result, agent.seen


async def test_a_recorded_episode_sees_and_scores_what_an_unrecorded_one_does(
    episode_runner: EpisodeRunner, content: TaskContent
) -> None:
    plain, plain_seen = await run(episode_runner, content, RecordSettings())
    filmed, filmed_seen = await run(episode_runner, content, RecordSettings(video=True, fps=10))
    assert plain.video is None
    assert len(set(plain_seen)) == 4  # the ball moved between the looks: page time passed at each step
    assert filmed_seen == plain_seen  # byte-identical pages: the screencast moved no page time
    assert [s.episode_clock_ms for s in filmed.steps] == [s.episode_clock_ms for s in plain.steps]
    assert [(s.ok, s.data) for s in filmed.steps] == [(s.ok, s.data) for s in plain.steps]
    assert filmed.evaluation is not None and plain.evaluation is not None
    assert filmed.outcome == plain.outcome
    assert [t.model_dump(exclude={"duration_ms"}) for t in filmed.evaluation.tests] == [
        t.model_dump(exclude={"duration_ms"}) for t in plain.evaluation.tests
    ]
    assert blocks_of(filmed) == blocks_of(plain)  # the same project, the dragged block where it was dropped

    video = filmed.video
    assert video is not None
    info = video.info
    assert (info.fps, info.width, info.height) == (10, 1280, 720)
    assert 2 <= info.frames <= info.received + 1  # the last frame is the page as it was at the end
    first_step = filmed.steps[0].started_at
    assert first_step is not None and info.started_at <= first_step  # recording began before the first look
    last = filmed.steps[-1]
    assert last.started_at is not None and info.started_at + info.duration_s >= last.started_at
    container = av.open(io.BytesIO(video.mp4))
    assert container.streams.video[0].codec_context.name == "h264"
    assert len(list(container.decode(video=0))) == info.frames


async def test_a_recording_ends_with_an_episode_that_breaks_off(
    episode_runner: EpisodeRunner, content: TaskContent
) -> None:
    class Crashes(AgentBase):
        observes = False

        async def act(self, observation: Observation | None, last: StepResult | None) -> Action:
            if last is None:
                return PrimitiveAction(api="click", args={"x": 640, "y": 360})
            raise RuntimeError("the agent broke")

    result = await episode_runner.run(episode(content, RecordSettings(video=True)), content.payload, Crashes())
    assert (result.outcome, result.error_class) == ("error", "agent_error")
    assert result.video is not None and result.video.info.frames >= 1  # what happened up to the crash is kept
    again = await episode_runner.run(episode(content, RecordSettings()), content.payload, DoneAtOnce())
    assert again.outcome in ("passed", "failed") and again.video is None  # the page went back clean


class DoneAtOnce(AgentBase):
    observes = False

    async def act(self, observation: Observation | None, last: StepResult | None) -> Action:
        return Done()
