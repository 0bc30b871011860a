"""The virtual episode clock: the agent's page stands still while the model thinks, so the same
scripted replies produce the same screenshots with a fast or a slow model and on an idle or a loaded
machine; on the real clock they do not."""

from __future__ import annotations

import contextlib
import hashlib
import json
import re
import subprocess
import sys
from collections.abc import Callable, Iterator
from typing import Any, NamedTuple

import pytest

from scratchworld_dist.kinds.tasks import EpisodeMatrix, TaskContent, plan_jobs, read_task
from scratchworld_dist.suites import load_suite
from scratchworld_dist.sweep import worker_job
from tests.conftest import SUITE_DIR, pooled_editor, primitive_editor
from tests.support.openai_server import Behaviour, OpenAIServer
from workers.actor import WorkerBrowser
from workers.agents import LLMAgent, OracleAgent
from workers.contract import BridgeError, EpisodeClock, ModelSpec, ObservationSettings, RetryPolicy, check_project
from workers.editor import BrowserSession, EditorPool
from workers.kinds.tasks import EpisodeRunner
from workers.kinds.tasks._pace import Pace
from workers.kinds.tasks._runner import sees_stage

pytestmark = [pytest.mark.usefixtures("litellm_clients"), pytest.mark.browser]

KEY_ENV = "SCRATCHWORLD_TEST_CLOCK_KEY"
FAST = RetryPolicy(max_attempts=2, initial_backoff_s=0.01, max_backoff_s=0.02, request_timeout_s=20, max_total_s=60)
SLOW_MODEL_S = 1.5


@pytest.fixture(autouse=True)
def api_key(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(KEY_ENV, "sk-clock-test")


@pytest.fixture(scope="module")
def content() -> TaskContent:
    # A ball that travels across the stage once its script runs: every frame shows on the stage.
    return read_task(load_suite(SUITE_DIR).task("bounce_speedup"))


@contextlib.contextmanager
def hogging_the_cpu() -> Iterator[None]:
    """Two busy processes, one per core of this machine, while the block runs."""
    hogs = [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(2)]
    try:
        yield
    finally:
        for hog in hogs:
            hog.kill()
            hog.wait()


def click_the_script_then_wait(delay_s: float) -> Callable[[dict[str, Any]], Behaviour]:
    """Click the green-flag script (it runs), then click empty workspace twice, then done; each
    reply comes after ``delay_s``."""
    turns = iter(range(4))

    def respond(body: dict[str, Any]) -> Behaviour:
        turn = next(turns)
        if turn == 0:
            text = body["messages"][-1]["content"][0]["text"]
            index = re.search(r"^(\d+)  blocks  event_whenflagclicked on canvas", text, re.MULTILINE)
            assert index is not None, text
            action: dict[str, Any] = {"api": "click", "args": {"index": int(index.group(1))}}
        elif turn < 3:
            action = {"api": "click", "args": {"x": 650, "y": 620}}
        else:
            action = {"api": "done"}
        return Behaviour("hang", text=f"```json\n{json.dumps(action)}\n```", seconds=delay_s)

    return respond


class Seen(NamedTuple):
    """What one primitive episode showed its model, and where it left the ball. A digest per screenshot keeps a
    failure's message readable; the ball's place (from the saved project) tells a VM that ran differently from
    a page that was only drawn differently."""

    pictures: list[str]
    ball: tuple[float, float]


def ball_position(sb3: bytes | None) -> tuple[float, float]:
    assert sb3 is not None
    (ball,) = [t for t in check_project(sb3)["targets"] if t.get("name") == "Ball"]
    return ball["x"], ball["y"]


async def screenshots_seen(runner: EpisodeRunner, content: TaskContent, clock: EpisodeClock, delay_s: float) -> Seen:
    """The screenshots the model was sent, in order, for one primitive episode."""
    with OpenAIServer(responder=click_the_script_then_wait(delay_s)) as server:
        model = ModelSpec(name="m", model="openai/gpt-4o-mini", api_base=server.url, api_key_env=KEY_ENV)
        settings = {"retry": FAST}
        (job,) = plan_jobs(
            EpisodeMatrix(
                models=[model],
                modes=["primitive"],
                agent="llm",
                tasks=[content],
                seeds=[3],
                max_steps=6,
                observation=ObservationSettings(ocr="none"),
            )
        )
        spec = worker_job(job, 1, 300)
        spec = spec.model_copy(update={"episode_clock": clock, "llm": spec.llm.model_copy(update=settings)})  # type: ignore[union-attr]
        result = await runner.run(spec, content.payload, LLMAgent())
        assert [step.action for step in result.steps] == ["click", "click", "click", "done"], result.error_message
        assert all(step.ok for step in result.steps)
        pictures = [
            hashlib.sha256(part["image_url"]["url"].encode()).hexdigest()[:16]
            for request in server.requests
            for part in request.body["messages"][-1]["content"]
            if part["type"] == "image_url"
        ]
        return Seen(pictures, ball_position(result.final_project))


VIRTUAL = EpisodeClock(mode="virtual", settle_ms=300)


async def test_a_slow_model_sees_what_a_fast_one_sees_on_the_virtual_clock(
    episode_runner: EpisodeRunner, content: TaskContent
) -> None:
    fast = await screenshots_seen(episode_runner, content, VIRTUAL, delay_s=0)
    slow = await screenshots_seen(episode_runner, content, VIRTUAL, delay_s=SLOW_MODEL_S)
    assert len(fast.pictures) == 4
    assert len(set(fast.pictures)) == 4  # the ball moved between the screenshots: they show time passing
    assert slow == fast


async def test_a_loaded_machine_and_a_recycled_editor_see_the_same_pages(
    session: BrowserSession, content: TaskContent
) -> None:
    idle = await screenshots_seen(EpisodeRunner(WorkerBrowser(session)), content, VIRTUAL, delay_s=0)  # a fresh editor
    with hogging_the_cpu():
        async with EditorPool(session, spare=0) as pool:
            first = await screenshots_seen(EpisodeRunner(WorkerBrowser(session, pool)), content, VIRTUAL, delay_s=0)
            again = await screenshots_seen(
                EpisodeRunner(WorkerBrowser(session, pool)), content, VIRTUAL, delay_s=0
            )  # recycled
            assert pool.reused >= 1
    assert first == idle  # a loaded machine
    assert again == idle  # and a recycled editor


async def test_on_the_real_clock_the_model_s_latency_shows_on_the_stage(
    episode_runner: EpisodeRunner, content: TaskContent
) -> None:
    """On recycled pages: the first pictures match only if the palette shows the loaded sprite's
    position, not where the last episode's sprite stopped (the GUI writes it on the real clock's
    next targets update, after the first look)."""
    fast = await screenshots_seen(episode_runner, content, EpisodeClock(mode="real"), delay_s=0)
    slow = await screenshots_seen(episode_runner, content, EpisodeClock(mode="real"), delay_s=SLOW_MODEL_S)
    assert fast.pictures[0] == slow.pictures[0]  # nothing runs before the first click
    assert fast.pictures[1:] != slow.pictures[1:]  # the ball went on moving while the slow model thought


async def gesture_pictures(
    pool: EditorPool, content: TaskContent, *, stage_seen: bool = True, filmed: bool = False
) -> tuple[bytes, bytes, bytes]:
    """The stage's picture with the ball running: before a gesture's page time, after it, and after the action."""
    async with primitive_editor(pool, content.payload.initial_project) as editor:
        pace = Pace(editor, VIRTUAL, stage_seen=stage_seen, filmed=filmed)
        await pace.start()
        await editor.page.get_by_role("button", name="Start project").click()
        await pace.after_action()
        stage = editor.page.locator("[class*='stage_stage'] canvas").first
        before = await stage.screenshot()
        for _ in range(5):  # a drag's moves
            await pace.pass_time(33)
        during = await stage.screenshot()
        await pace.after_action()
        return before, during, await stage.screenshot()


async def test_the_stage_is_drawn_where_the_agent_looks_or_when_filmed(
    shared_pool: EditorPool, content: TaskContent
) -> None:
    """Between a drag's moves the VM runs on but the stage is not drawn (each picture cost the browser more
    than the move); the action's end draws it, so every picture an agent is shown is the same either way.
    A video draws it throughout; an agent that never looks at it never has it drawn."""
    before, during, after = await gesture_pictures(shared_pool, content, filmed=False)
    assert during == before and after != before  # the ball moved, and was drawn once the action ended
    filmed_before, filmed_during, filmed_after = await gesture_pictures(shared_pool, content, filmed=True)
    assert filmed_during != filmed_before  # a video shows the ball moving during the gesture
    assert (filmed_before, filmed_after) == (before, after)
    # An agent that never looks at the stage (composite, unprivileged) has it drawn never: the start's picture.
    assert len(set(await gesture_pictures(shared_pool, content, stage_seen=False))) == 1
    assert len(set(await gesture_pictures(shared_pool, content, stage_seen=False, filmed=True))) == 3
    async with pooled_editor(shared_pool) as editor:
        await editor.start_episode_clock(VIRTUAL)
        with pytest.raises(BridgeError, match="draw must be true or false"):
            await editor.call("advanceClock", {"ms": 0, "draw": "no"})


def test_only_agents_that_may_look_at_the_stage_have_it_drawn() -> None:
    assert not sees_stage("composite", LLMAgent())  # text observations only
    assert sees_stage("primitive", LLMAgent())  # screenshots
    assert sees_stage("composite", OracleAgent())  # privileged: it holds the live page
