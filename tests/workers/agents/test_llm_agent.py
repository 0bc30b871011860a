"""The llm agent in real episodes: real Chromium, real LiteLLM, a real local OpenAI-compatible server."""

from __future__ import annotations

import dataclasses
import json
from collections.abc import Iterator
from typing import Any

import pytest

from scratchworld_dist.kinds.tasks import EpisodeMatrix, TaskContent, plan_jobs, read_task
from scratchworld_dist.suites import load_suite
from scratchworld_dist.sweep import worker_job
from tests.conftest import SUITE_DIR
from tests.support.openai_server import OpenAIServer, reply, status
from workers.agent_api import TaskContext
from workers.agents import EpisodeModels, LLMAgent
from workers.agents._coordinates import smart_resize, to_page
from workers.contract import (
    EpisodeClock,
    LLMSettings,
    Mode,
    ModelSpec,
    ObservationSettings,
    PrimitiveObservation,
    RetryPolicy,
)
from workers.kinds.tasks import EpisodeRunner, EpisodeSpec
from workers.kinds.tasks._pace import ACTION_LEAD_MS
from workers.llm import load_litellm

FAST = RetryPolicy(max_attempts=2, initial_backoff_s=0.01, max_backoff_s=0.02, request_timeout_s=10, max_total_s=30)
pytestmark = [pytest.mark.usefixtures("litellm_clients"), pytest.mark.browser]

KEY_ENV = "SCRATCHWORLD_TEST_AGENT_KEY"
SECRET = "sk-agent-test-5d1e9b27c4"


@pytest.fixture(autouse=True)
def api_key(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(KEY_ENV, SECRET)


@pytest.fixture(scope="module")
def content() -> TaskContent:
    return read_task(load_suite(SUITE_DIR).task("quiz_score"))


@pytest.fixture
def server() -> Iterator[OpenAIServer]:
    with OpenAIServer() as running:
        yield running


def answer(action: dict[str, Any], prose: str = "I look at the blocks.") -> str:
    return f"Analysis: {prose}\n```json\n{json.dumps(action)}\n```"


def episode(
    content: TaskContent,
    server: OpenAIServer,
    mode: Mode = "composite",
    model: str = "openai/gpt-4o-mini",
    llm: LLMSettings | None = None,
    max_steps: int = 40,
    clock: EpisodeClock | None = None,
) -> EpisodeSpec:
    spec = ModelSpec(name="m", model=model, api_base=server.url, api_key_env=KEY_ENV)
    settings = (llm or LLMSettings()).model_copy(update={"retry": FAST})
    observation = ObservationSettings(ocr="none") if mode == "primitive" else None
    (job,) = plan_jobs(
        EpisodeMatrix(
            models=[spec],
            modes=[mode],
            agent="llm",
            tasks=[content],
            seeds=[7],
            max_steps=max_steps,
            observation=observation,
            llm=settings,
            episode_clock=clock,
        )
    )
    return worker_job(job, 1, 300)


async def no_catalog() -> None:
    return None


def context_for(spec: EpisodeSpec, content: TaskContent, models: EpisodeModels) -> TaskContext:
    """The context an episode would give the agent, without an editor."""
    return TaskContext(
        task_id=content.task.id,
        category=content.task.category,
        instruction=content.payload.instruction,
        mode=spec.mode,
        max_steps=spec.max_steps,
        seed=spec.seed,
        block_catalog=no_catalog,
        model=spec.model,
        connect=models.connect,
        llm=spec.llm,
    )


def user_texts(body: dict[str, Any]) -> list[str]:
    """The text of every user message of a request, image parts left out."""
    texts = []
    for message in body["messages"]:
        if message["role"] != "user":
            continue
        content = message["content"]
        parts = content if isinstance(content, list) else [{"type": "text", "text": content}]
        texts.append("\n".join(p["text"] for p in parts if p["type"] == "text"))
    return texts


def image_parts(body: dict[str, Any]) -> int:
    return sum(
        1
        for message in body["messages"]
        if isinstance(message["content"], list)
        for part in message["content"]
        if part["type"] == "image_url"
    )


async def test_canned_replies_solve_a_task_in_composite_mode(
    episode_runner: EpisodeRunner, content: TaskContent, server: OpenAIServer
) -> None:
    trajectory = [a.model_dump(mode="json", include={"api", "args"}) for a in content.payload.golden_trajectory or []]
    replies = [reply(answer(a), prompt_tokens=1000, completion_tokens=100) for a in trajectory]
    replies[0] = dataclasses.replace(replies[0], reasoning="First the hat block.")  # as reasoning models send it
    server.push(*replies)
    server.push(reply(answer({"api": "done", "args": {}}), prompt_tokens=1000, completion_tokens=100))
    spec = episode(content, server, clock=EpisodeClock(mode="virtual"))
    result = await episode_runner.run(spec, content.payload, LLMAgent())

    assert result.outcome == "passed", result.evaluation
    assert result.stop_reason == "done"
    assert len(result.steps) == len(trajectory) + 1 == server.count
    assert all(step.ok for step in result.steps)
    # Each step keeps the text it was shown, whatever the agent made of it.
    first = result.steps[0].observation
    assert first is not None and first.text and first.screenshot is None
    assert first.text in str(server.requests[0].body["messages"][1]["content"])
    # Accounting: exact LiteLLM prices of gpt-4o-mini for the billed tokens, summed per step and job.
    litellm = await load_litellm()
    price = litellm.model_cost["gpt-4o-mini"]
    per_call = 1000 * price["input_cost_per_token"] + 100 * price["output_cost_per_token"]
    assert all(step.llm_calls == 1 and step.cost_usd == pytest.approx(per_call) for step in result.steps)
    assert (result.input_tokens, result.output_tokens) == (1000 * server.count, 100 * server.count)
    assert result.cost_usd == pytest.approx(per_call * server.count)
    # The system prompt: instruction, API catalog, block catalog from the editor, response rule.
    first = server.requests[0].body
    system = first["messages"][0]["content"]
    assert first["messages"][0]["role"] == "system"
    assert content.payload.instruction in system
    assert "connect_blocks" in system and "control_if_else (c): CONDITION <boolean>" in system
    assert "Analysis:" in system and "```json" in system
    assert "## Blocks Pseudocode" in user_texts(first)[-1]
    assert first["seed"] == 7
    assert server.requests[0].headers["authorization"] == f"Bearer {SECRET}"
    # The trajectory keeps prompts and raw replies: the system prompt once, then one user message per step.
    assert [m["role"] for m in result.steps[0].prompt] == ["system", "user"]  # type: ignore[index]
    assert [m["role"] for m in result.steps[1].prompt] == ["user"]  # type: ignore[index]
    assert result.steps[0].reply == answer(trajectory[0])
    # The provider's reasoning is kept beside the reply; each step records when it began and the page's time then.
    assert result.steps[0].reasoning == "First the hat block." and result.steps[1].reasoning is None
    began = [step.started_at for step in result.steps]
    assert None not in began and began == sorted(began) and began[0] >= result.started_at  # type: ignore[type-var]
    clock = spec.episode_clock
    assert clock.mode == "virtual"
    expected = [clock.start_ms + k * (ACTION_LEAD_MS + clock.step_ms) for k in range(len(result.steps))]
    assert [step.episode_clock_ms for step in result.steps] == expected
    # The previous action's result is shown: add_block's data names the new block's index.
    assert user_texts(server.requests[3].body)[-1].startswith("Result of your previous action: success.")
    # History is bounded: system prompt plus at most 21 messages, starting with a user message.
    last = server.requests[-1].body["messages"]
    assert last[0]["role"] == "system" and last[1]["role"] == "user" and len(last) <= 22


async def test_an_unparsable_reply_costs_the_step_and_is_fed_back(
    episode_runner: EpisodeRunner, content: TaskContent, server: OpenAIServer
) -> None:
    server.push(
        reply("I would add a block now, but I am not sure which one."),
        reply(answer({"api": "add_block", "args": {"blockType": "no_such_block"}})),
        reply(answer({"api": "done"})),
    )
    spec = episode(content, server)
    result = await episode_runner.run(spec, content.payload, LLMAgent())
    unparsable, refused, done = result.steps
    assert (unparsable.action, unparsable.ok, unparsable.error_code) == ("invalid_reply", False, "INVALID_REPLY")
    assert unparsable.llm_calls == 1  # a wasted step still costs its call
    second, third = (user_texts(r.body)[-1] for r in server.requests[1:])
    assert second.startswith("Result of your previous action: error INVALID_REPLY:")
    assert "```json" in second  # the expected format is repeated
    assert (refused.ok, refused.error_code) == (False, "INVALID_ARG")
    assert third.startswith("Result of your previous action: error INVALID_ARG: unknown block type")
    assert done.action == "done"
    assert result.outcome == "failed"  # evaluation ran although nothing was built


async def test_the_papers_protocol_shows_no_results(
    episode_runner: EpisodeRunner, content: TaskContent, server: OpenAIServer
) -> None:
    server.push(reply("no action here"), reply(answer({"api": "done"})))
    spec = episode(content, server, llm=LLMSettings(show_action_result=False))
    await episode_runner.run(spec, content.payload, LLMAgent())
    assert not any("Result of your previous action" in text for text in user_texts(server.requests[1].body))


async def test_a_permanent_model_error_ends_the_job_with_its_class(
    episode_runner: EpisodeRunner, content: TaskContent, server: OpenAIServer
) -> None:
    server.push(reply(answer({"api": "add_block", "args": {"blockType": "looks_say"}})), status(401))
    spec = episode(content, server)
    result = await episode_runner.run(spec, content.payload, LLMAgent())
    assert (result.outcome, result.error_class) == ("error", "model_auth")
    assert len(result.steps) == 1 and result.steps[0].ok  # what happened before is kept
    assert SECRET not in (result.error_message or "")
    assert server.count == 2  # a 401 is not retried


async def test_primitive_turns_send_the_newest_screenshot_and_map_model_coordinates(
    episode_runner: EpisodeRunner, content: TaskContent, server: OpenAIServer
) -> None:
    # A Qwen-VL model answers in 0-1000 coordinates: (500, 500) is the centre of the page.
    server.push(
        reply(answer({"api": "click", "args": {"x": 500, "y": 500}})),
        reply(answer({"api": "scroll", "args": {"direction": "down", "x": 100, "y": 900}})),
        reply(answer({"api": "done"})),
    )
    spec = episode(content, server, mode="primitive", model="openai/qwen3-vl-8b")
    agent = LLMAgent()
    result = await episode_runner.run(spec, content.payload, agent)
    click, scroll, _ = result.steps
    assert (click.action, click.args, click.ok) == ("click", {"x": 640.0, "y": 360.0}, True)
    assert (scroll.args["x"], scroll.args["y"]) == (128.0, 648.0)
    system = server.requests[0].body["messages"][0]["content"]
    assert "normalised to 0-1000" in system and "index  type  text  (x, y) WxH" in system
    assert "drag_and_drop" in system and "add_block" not in system
    assert [image_parts(r.body) for r in server.requests] == [1, 1, 1]  # only the newest screenshot
    first_user = server.requests[0].body["messages"][1]["content"]
    assert first_user[0]["text"].startswith("Element list:\n0  ")
    assert first_user[1]["image_url"]["url"].startswith("data:image/png;base64,")
    # Images are kept once by hash and referenced from the recorded prompts.
    recorded = [m for step in result.steps for m in step.prompt if isinstance(m["content"], list)]  # type: ignore[index]
    refs = [part["sha256"] for m in recorded for part in m["content"] if part["type"] == "image_ref"]  # type: ignore[index,union-attr]
    assert len(refs) == 3 and set(refs) == set(result.images)
    assert all(png.startswith(b"\x89PNG") for png in result.images.values())


@pytest.mark.parametrize(("last_only", "images"), [(True, [1, 1, 1, 1]), (False, [1, 2, 2, 2])])
async def test_history_window_and_screenshots_follow_the_settings(
    content: TaskContent, server: OpenAIServer, last_only: bool, images: list[int]
) -> None:
    server.push(*(reply(answer({"api": "click", "args": {"x": 1, "y": 2}})) for _ in range(4)))
    settings = LLMSettings(history_messages=4, last_screenshot_only=last_only)
    spec = episode(content, server, mode="primitive", llm=settings)
    models = EpisodeModels(FAST, spec.seed)
    agent = LLMAgent()
    await agent.start(context_for(spec, content, models))
    for turn in range(4):
        png = b"\x89PNG-turn-" + bytes([turn])
        observation = PrimitiveObservation(screenshot_png=png, elements=[], text=f"{turn}  canvas", settled=True)
        await agent.act(observation, None)
        models.drain()
    assert [image_parts(r.body) for r in server.requests] == images
    # System prompt, then at most 4 messages that start with a user turn.
    assert [[m["role"] for m in r.body["messages"]] for r in server.requests] == [
        ["system", "user"],
        ["system", "user", "assistant", "user"],
        ["system", "user", "assistant", "user"],
        ["system", "user", "assistant", "user"],
    ]
    assert len(models.images) == 4


def test_coordinate_conventions() -> None:
    assert smart_resize(1280, 720) == (1288, 728)
    assert to_page({"x": 1288, "y": 728, "index": 3}, "smart_resize") == {"x": 1280.0, "y": 720.0, "index": 3}
    assert to_page({"start_x": 0, "start_y": 1000, "end_x": 250, "end_y": "a"}, "normalized_1000") == {
        "start_x": 0.0,
        "start_y": 720.0,
        "end_x": 320.0,
        "end_y": "a",
    }
    assert to_page({"x": 5, "y": 6}, "pixels") == {"x": 5, "y": 6}
