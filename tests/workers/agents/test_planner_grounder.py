"""The planner_grounder agent in real episodes: real Chromium, real LiteLLM, two real local OpenAI-compatible
servers (a planner that names targets in words, a UI-TARS-style grounder that points at them).

The scripts are derived from the primitive oracle's own gestures on a task of the suite: the planner
replays each gesture with every position replaced by a description, and the grounder answers each
description with the oracle's position written in UI-TARS's smart-resize space (1288x728 for the
1280x720 page). The task is solved only if the agent grounds every description and maps every point
back to the page pixels the oracle used."""

from __future__ import annotations

import json
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import pytest

from scratchworld_dist.kinds.tasks import EpisodeMatrix, TaskContent, plan_jobs, read_task
from scratchworld_dist.suites import load_suite
from scratchworld_dist.sweep import worker_job
from tests.conftest import SUITE_DIR
from tests.support.openai_server import OpenAIServer, reply
from workers.agent_api import build_agent
from workers.agents import OracleAgent
from workers.contract import AgentRef, JobResult, LLMSettings, ModelSpec, ObservationSettings, RetryPolicy
from workers.kinds.tasks import EpisodeRunner

pytestmark = [pytest.mark.usefixtures("litellm_clients"), pytest.mark.browser]

TASK = "bouncing_ball_stuck"
"""A debug task whose primitive solution is four drags (eight positions to ground)."""

FAST = RetryPolicy(max_attempts=2, initial_backoff_s=0.01, max_backoff_s=0.02, request_timeout_s=10, max_total_s=30)
PLANNER_ENV, PLANNER_KEY = "SCRATCHWORLD_TEST_PLANNER_KEY", "sk-planner-test-8c21f0"
GROUNDER_ENV, GROUNDER_KEY = "SCRATCHWORLD_TEST_GROUNDER_KEY", "sk-grounder-test-3e97ab"

MODEL_SPACE = (1288, 728)
"""UI-TARS answers in the pixels of the screenshot as its processor smart-resizes it (multiples of 28)."""

PAGE = (1280, 720)
POSITIONS = (
    ("description", "x", "y", "point"),
    ("source_description", "start_x", "start_y", "source"),
    ("target_description", "end_x", "end_y", "target"),
)


@dataclass(frozen=True)
class Gesture:
    """One oracle step: its action and its args in page pixels."""

    api: str
    args: dict[str, Any]


@dataclass(frozen=True)
class Target:
    """A position the planner names in words and the grounder points at."""

    step: int
    description: str
    x: float
    y: float


@pytest.fixture(autouse=True)
def api_keys(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(PLANNER_ENV, PLANNER_KEY)
    monkeypatch.setenv(GROUNDER_ENV, GROUNDER_KEY)


@pytest.fixture(scope="module")
def content() -> TaskContent:
    return read_task(load_suite(SUITE_DIR).task(TASK))


@pytest.fixture(scope="module")
async def gestures(episode_runner: EpisodeRunner, content: TaskContent) -> list[Gesture]:
    """The privileged oracle's primitive solution, as the episode recorded it."""
    (job,) = plan_jobs(
        EpisodeMatrix(
            models=[None],
            modes=["primitive"],
            agent=AgentRef(name="oracle"),
            tasks=[content],
            seeds=[7],
            max_steps=40,
            observation=ObservationSettings(ocr="none"),
        )
    )
    result = await episode_runner.run(worker_job(job, 1, 300), content.payload, OracleAgent())
    assert result.outcome == "passed", result.evaluation
    *moves, done = result.steps
    assert done.action == "done" and moves and all(step.ok for step in moves)
    return [Gesture(step.action, dict(step.args)) for step in moves]


@pytest.fixture
def planner() -> Iterator[OpenAIServer]:
    with OpenAIServer() as running:
        yield running


@pytest.fixture
def grounder() -> Iterator[OpenAIServer]:
    with OpenAIServer() as running:
        yield running


def answer(action: dict[str, Any]) -> str:
    return f"Analysis: I act on what I see.\n```json\n{json.dumps(action)}\n```"


def described(gestures: list[Gesture]) -> tuple[list[dict[str, Any]], list[Target]]:
    """The planner's actions (every position replaced by a description) and the positions they name, in order."""
    actions, targets = [], []
    for number, gesture in enumerate(gestures, start=1):
        args = dict(gesture.args)
        for key, x_key, y_key, role in POSITIONS:
            if x_key in args:
                words = f"step {number} {role}"
                targets.append(Target(number - 1, words, float(args.pop(x_key)), float(args.pop(y_key))))
                args[key] = words
        actions.append({"api": gesture.api, "args": args})
    return actions, targets


def point(x: float, y: float) -> str:
    """A page position as UI-TARS writes it: in smart-resize space, two decimals (0.05 px back on the page)."""
    return f"({x * MODEL_SPACE[0] / PAGE[0]:.2f},{y * MODEL_SPACE[1] / PAGE[1]:.2f})"


async def run_agent(
    episode_runner: EpisodeRunner, content: TaskContent, planner: OpenAIServer, grounder: OpenAIServer
) -> JobResult:
    planner_spec = ModelSpec(name="planner", model="openai/gpt-4o-mini", api_base=planner.url, api_key_env=PLANNER_ENV)
    grounder_spec = ModelSpec(
        name="ui-tars", model="openai/ui-tars-1.5-7b", api_base=grounder.url, api_key_env=GROUNDER_ENV
    )
    ref = AgentRef(name="planner_grounder", params={"grounder": grounder_spec.model_dump(mode="json")})
    settings = LLMSettings(retry=FAST)
    matrix = EpisodeMatrix(
        models=[planner_spec],
        modes=["primitive"],
        agent=ref,
        tasks=[content],
        seeds=[7],
        max_steps=40,
        observation=ObservationSettings(ocr="none"),
        llm=settings,
        extra_models=[grounder_spec],
    )
    (job,) = plan_jobs(matrix)
    assert job.model_name == "planner+ui-tars"
    return await episode_runner.run(worker_job(job, 1, 300), content.payload, build_agent(ref))


def image_urls(body: dict[str, Any]) -> list[str]:
    return [
        part["image_url"]["url"]
        for message in body["messages"]
        if isinstance(message["content"], list)
        for part in message["content"]
        if part["type"] == "image_url"
    ]


def texts(body: dict[str, Any]) -> str:
    return "\n".join(
        part["text"]
        for message in body["messages"]
        for part in (message["content"] if isinstance(message["content"], list) else [{"text": message["content"]}])
        if "text" in part
    )


async def test_a_planner_and_a_grounder_solve_a_primitive_task(
    episode_runner: EpisodeRunner,
    content: TaskContent,
    gestures: list[Gesture],
    planner: OpenAIServer,
    grounder: OpenAIServer,
) -> None:
    actions, targets = described(gestures)
    assert len(targets) >= 2 * len(gestures)  # drags: a source and a target each
    planner.push(*(reply(answer(action), prompt_tokens=1000, completion_tokens=50) for action in actions))
    planner.push(reply(answer({"api": "done", "args": {}}), prompt_tokens=1000, completion_tokens=50))
    grounder.push(*(reply(point(t.x, t.y)) for t in targets))

    result = await run_agent(episode_runner, content, planner, grounder)

    assert result.outcome == "passed", result.evaluation
    assert result.stop_reason == "done"
    *moves, done = result.steps
    assert done.action == "done" and all(step.ok for step in result.steps)
    # Every gesture ran where the oracle's did: the grounder's points mapped back to page pixels.
    assert [step.action for step in moves] == [gesture.api for gesture in gestures]
    for step, gesture in zip(moves, gestures, strict=True):
        assert set(step.args) == set(gesture.args)
        for key, value in gesture.args.items():
            expected = pytest.approx(value, abs=0.1) if isinstance(value, float) else value
            assert step.args[key] == expected, (step.index, key)
    # One planner call per step; one grounder call per description, in order, each with the screenshot.
    assert planner.count == len(result.steps)
    assert grounder.count == len(targets)
    for request, target in zip(grounder.requests, targets, strict=True):
        assert request.body["model"] == "ui-tars-1.5-7b"
        assert request.headers["authorization"] == f"Bearer {GROUNDER_KEY}"
        (url,) = image_urls(request.body)
        assert url.startswith("data:image/png;base64,")
        assert f"Query: {target.description}\n" in texts(request.body)
        # The grounder sees the screenshot the planner decided on.
        assert url == image_urls(planner.requests[target.step].body)[-1]
    assert all(r.headers["authorization"] == f"Bearer {PLANNER_KEY}" for r in planner.requests)
    system = planner.requests[0].body["messages"][0]["content"]
    assert content.payload.instruction in system and "source_description" in system
    # Accounting: each step counts its planner call and its grounder calls.
    grounded = [sum(t.step == index for t in targets) for index in range(len(result.steps))]
    assert [step.llm_calls for step in result.steps] == [1 + n for n in grounded]
    assert all(step.cost_usd > 0 for step in result.steps)  # the planner's gpt-4o-mini price at least
    assert result.input_tokens == 1000 * planner.count + 10 * grounder.count


async def test_a_misgrounded_drop_fails_the_task(
    episode_runner: EpisodeRunner,
    content: TaskContent,
    gestures: list[Gesture],
    planner: OpenAIServer,
    grounder: OpenAIServer,
) -> None:
    actions, targets = described(gestures)
    planner.push(*(reply(answer(action)) for action in [*actions, {"api": "done", "args": {}}]))
    # The last drop lands in empty workspace instead of the connection point the oracle aimed at.
    *right, last = targets
    assert last.description.endswith("target")
    grounder.push(*(reply(point(t.x, t.y)) for t in right), reply(point(700, 620)))

    result = await run_agent(episode_runner, content, planner, grounder)

    assert grounder.count == len(targets)
    assert all(step.ok for step in result.steps)  # every gesture ran; the drop just missed
    assert (result.steps[-2].args["end_x"], result.steps[-2].args["end_y"]) == (700.0, 620.0)
    assert result.outcome == "failed", result.evaluation
