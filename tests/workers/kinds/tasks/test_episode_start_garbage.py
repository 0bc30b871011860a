"""An episode's page drops its start garbage once it first waits for a model, and never when it calls none.

Real episodes in a real browser; a real local OpenAI-compatible server holds the model's first answer, and the
editor's own collection is watched (it still runs) to see when the runner asks for it.
"""

from __future__ import annotations

import asyncio
from collections.abc import Iterator

import pytest

from scratchworld_dist.kinds.tasks import TaskContent, read_task
from scratchworld_dist.suites import load_suite
from tests.conftest import SUITE_DIR
from tests.support.openai_server import OpenAIServer
from tests.workers.kinds.tasks.test_episode_starts import KEY_ENV, episode, until
from workers.actor import WorkerBrowser
from workers.agent_api import AgentBase, StepResult, TaskContext
from workers.contract import Action, Done, ModelSpec, Observation
from workers.editor import BrowserSession, Editor, EditorPool
from workers.kinds.tasks import EpisodeRunner

pytestmark = [pytest.mark.browser, pytest.mark.usefixtures("litellm_clients")]


@pytest.fixture(scope="module")
def content() -> TaskContent:
    return read_task(load_suite(SUITE_DIR).task("sum_two_numbers"))


@pytest.fixture
def server(monkeypatch: pytest.MonkeyPatch) -> Iterator[OpenAIServer]:
    monkeypatch.setenv(KEY_ENV, "sk-garbage")
    with OpenAIServer() as running:
        yield running


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
