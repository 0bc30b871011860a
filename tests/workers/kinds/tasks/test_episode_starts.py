"""Episodes of one runner start one at a time, each until its agent's first observation or first model call; a
page drops its start garbage once it first waits for a model, and never when it calls none.

Two real episodes share a real browser; plugin agents write down when they start and act, and a real local
OpenAI-compatible server holds the one model call until the test lets it answer. The editor's own collection is
watched (it still runs) to see when the runner asks for it.
"""

from __future__ import annotations

import asyncio
import time
from collections.abc import Awaitable, Callable, Iterator

import pytest

from scratchworld_dist.kinds.tasks import EpisodeMatrix, TaskContent, plan_jobs, read_task
from scratchworld_dist.suites import load_suite
from scratchworld_dist.sweep import worker_job
from tests.conftest import SUITE_DIR
from tests.support.openai_server import OpenAIServer
from workers.actor import WorkerBrowser
from workers.agent_api import AgentBase, StepResult, TaskContext
from workers.contract import Action, Done, EpisodeClock, LLMSettings, ModelSpec, Observation, RetryPolicy
from workers.editor import BrowserSession, Editor, EditorPool
from workers.kinds.tasks import EpisodeRunner, EpisodeSpec

pytestmark = [pytest.mark.browser, pytest.mark.usefixtures("litellm_clients")]

KEY_ENV = "SCRATCHWORLD_TEST_STARTS_KEY"
Looking = Callable[[], Awaitable[None]]


@pytest.fixture(scope="module")
def content() -> TaskContent:
    return read_task(load_suite(SUITE_DIR).task("sum_two_numbers"))


@pytest.fixture
def server(monkeypatch: pytest.MonkeyPatch) -> Iterator[OpenAIServer]:
    monkeypatch.setenv(KEY_ENV, "sk-starts")
    with OpenAIServer() as running:
        yield running


def episode(content: TaskContent, seed: int, model: ModelSpec | None = None) -> EpisodeSpec:
    retry = RetryPolicy(max_attempts=1, request_timeout_s=120, max_total_s=120)
    (job,) = plan_jobs(
        EpisodeMatrix(
            models=[model],
            modes=["composite"],
            agent="noop",
            tasks=[content],
            seeds=[seed],
            max_steps=3,
            llm=LLMSettings(retry=retry),
        )
    )
    return worker_job(job, 1, 120).model_copy(update={"episode_clock": EpisodeClock(mode="virtual")})


async def until(condition: Callable[[], bool], what: str) -> None:
    deadline = time.monotonic() + 60
    while not condition():
        assert time.monotonic() < deadline, f"never: {what}"
        await asyncio.sleep(0.01)


class Noting(AgentBase):
    """Writes ``<name> start``, ``<name> answered`` (after a model call in its start, if ``calls``) and ``<name> act``;
    ``before_looking`` is awaited at the end of its start."""

    def __init__(self, name: str, log: list[str], calls: bool = False, before_looking: Looking | None = None) -> None:
        super().__init__()
        self.name, self.log, self.calls, self.before_looking = name, log, calls, before_looking

    async def start(self, context: TaskContext) -> None:
        self.log.append(f"{self.name} start")
        if self.calls:
            await context.model().complete([{"role": "user", "content": "plan first"}])
            self.log.append(f"{self.name} answered")
        if self.before_looking is not None:
            await self.before_looking()

    async def act(self, observation: Observation | None, last: StepResult | None) -> Action:
        self.log.append(f"{self.name} act")
        return Done()


async def test_the_next_episode_starts_only_once_the_first_has_made_its_first_observation(
    session: BrowserSession, shared_pool: EditorPool, content: TaskContent
) -> None:
    runner = EpisodeRunner(WorkerBrowser(session, shared_pool))
    log: list[str] = []

    async def second_queued() -> None:  # the first holds its turn into its first observation
        await until(lambda: runner.waiting_to_start == 1, "the second episode queued for its start")

    first = asyncio.ensure_future(
        runner.run(episode(content, 0), content.payload, Noting("A", log, False, second_queued))
    )
    await until(lambda: log == ["A start"], "the first agent started")
    second = asyncio.ensure_future(runner.run(episode(content, 1), content.payload, Noting("B", log)))
    results = await asyncio.gather(first, second)

    assert log == ["A start", "A act", "B start", "B act"]
    assert [result.outcome for result in results] == ["failed", "failed"]  # done at once: judged, not an error
    assert runner.waiting_to_start == 0


async def test_a_model_call_in_an_agent_s_start_lets_the_next_episode_start(
    session: BrowserSession, shared_pool: EditorPool, content: TaskContent, server: OpenAIServer
) -> None:
    runner = EpisodeRunner(WorkerBrowser(session, shared_pool))
    model = ModelSpec(name="m", model="openai/m", api_base=server.url, api_key_env=KEY_ENV)
    log: list[str] = []
    server.hold()

    first = asyncio.ensure_future(runner.run(episode(content, 0, model), content.payload, Noting("A", log, True)))
    await until(lambda: server.count == 1, "the first agent's model call arrived")
    second = asyncio.ensure_future(runner.run(episode(content, 1), content.payload, Noting("B", log)))
    await until(lambda: "B start" in log, "the second episode started while the first's model call waited")
    server.release()
    results = await asyncio.gather(first, second)

    assert log.index("B start") < log.index("A answered") < log.index("A act")
    assert [result.outcome for result in results] == ["failed", "failed"]


@pytest.fixture
def collections(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """The pages (by address) whose garbage the runner had collected, in order; each collection still runs."""
    seen: list[str] = []
    collect = Editor.collect_garbage

    async def watched(editor: Editor) -> None:
        seen.append(editor.page.url)
        await collect(editor)

    monkeypatch.setattr(Editor, "collect_garbage", watched)
    return seen


class Asking(AgentBase):
    """Calls the model in its start and again before its one action (if ``asks``), which is done."""

    def __init__(self, asks: bool) -> None:
        super().__init__()
        self.asks = asks
        self.context: TaskContext | None = None

    async def start(self, context: TaskContext) -> None:
        self.context = context
        if self.asks:
            await context.model().complete([{"role": "user", "content": "plan"}])

    async def act(self, observation: Observation | None, last: StepResult | None) -> Action:
        if self.asks and self.context is not None:
            await self.context.model().complete([{"role": "user", "content": "act"}])
        return Done()


async def test_the_start_garbage_is_collected_while_the_first_model_call_waits_and_only_then(
    session: BrowserSession, shared_pool: EditorPool, content: TaskContent, server: OpenAIServer, collections: list[str]
) -> None:
    runner = EpisodeRunner(WorkerBrowser(session, shared_pool))
    model = ModelSpec(name="m", model="openai/m", api_base=server.url, api_key_env=KEY_ENV)
    server.hold()
    running = asyncio.ensure_future(runner.run(episode(content, 0, model), content.payload, Asking(asks=True)))
    await until(lambda: server.count == 1, "the agent's first model call arrived")
    await until(lambda: len(collections) == 1, "the page's garbage was collected while the model had not answered")
    assert not running.done()
    server.release()
    result = await running

    assert server.count == 2  # the start's call and the action's: the second collects nothing more
    assert len(collections) == 1
    assert result.outcome == "failed"  # judged: the collection changed nothing the episode did


async def test_an_episode_that_calls_no_model_leaves_its_garbage_to_v8(
    session: BrowserSession, shared_pool: EditorPool, content: TaskContent, collections: list[str]
) -> None:
    runner = EpisodeRunner(WorkerBrowser(session, shared_pool))
    result = await runner.run(episode(content, 1), content.payload, Asking(asks=False))

    assert result.outcome == "failed"
    assert collections == []
