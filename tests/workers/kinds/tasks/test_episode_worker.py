"""The worker actor's class used in-process with its own real browser: episodes, timeouts, a dying browser."""

from __future__ import annotations

import asyncio
import contextlib
import os
from collections.abc import AsyncIterator
from pathlib import Path

import psutil
import pytest
from pydantic import BaseModel

from scratchworld_dist.kinds.tasks import EpisodeMatrix, TaskContent, plan_jobs, read_task
from scratchworld_dist.suites import load_suite
from scratchworld_dist.sweep import JobSpec, worker_job
from tests.conftest import REPO, SUITE_DIR
from tests.support.browser_pages import crash_renderer, editor_pages
from tests.support.openai_server import OpenAIServer, reply
from workers.actor import JobWorker, WorkerBrowser
from workers.actor._browser import EVALUATIONS_AT_ONCE
from workers.agent_api import AgentBase, StepResult, build_agent
from workers.contract import (
    Action,
    AgentRef,
    Done,
    LLMSettings,
    LoadProject,
    Mode,
    ModelSpec,
    Observation,
    RetryPolicy,
    SyntheticEpisodes,
    TaskPayload,
    evaluation_seed,
    with_random_seed,
)
from workers.editor import BrowserSession
from workers.kinds import kind_fingerprint
from workers.kinds.perception import PerceptionPayload, PerceptionSpec
from workers.kinds.tasks import EpisodeRunner, EpisodeSpec
from workers.node import harness_fingerprint, thread_policies
from workers.primitive import PRIMITIVE_APIS

pytestmark = pytest.mark.browser


@pytest.fixture(scope="module")
def contents() -> dict[str, TaskContent]:
    suite = load_suite(SUITE_DIR)
    return {task_id: read_task(suite.task(task_id)) for task_id in ("sum_two_numbers", "bouncing_ball_stuck")}


@pytest.fixture
async def worker() -> AsyncIterator[JobWorker]:
    worker = JobWorker(worker_index=3)
    yield worker
    await worker.close()


def episode(
    content: TaskContent,
    agent: AgentRef | str = "oracle",
    timeout_s: float = 120,
    mode: Mode = "composite",
    max_steps: int = 60,
) -> tuple[EpisodeSpec, TaskPayload]:
    (job,) = plan_jobs(
        EpisodeMatrix(models=[None], modes=[mode], agent=agent, tasks=[content], seeds=[0], max_steps=max_steps)
    )
    return worker_job(job, 1, timeout_s), content.payload


DONE_REPLY = 'Analysis: finished.\n```json\n{"api": "done", "args": {}}\n```'


def held_llm_job(server: OpenAIServer, content: TaskContent, monkeypatch: pytest.MonkeyPatch) -> JobSpec:
    """An ``llm`` job against ``server``, whose replies are held until ``release``; a model call may wait 120 s."""
    monkeypatch.setenv("SCRATCHWORLD_TEST_HELD_KEY", "sk-held")
    server.hold()
    model = ModelSpec(name="m", model="openai/m", api_base=server.url, api_key_env="SCRATCHWORLD_TEST_HELD_KEY")
    retry = RetryPolicy(max_attempts=1, request_timeout_s=120, max_total_s=120)
    (job,) = plan_jobs(
        EpisodeMatrix(
            models=[model],
            modes=["composite"],
            agent="llm",
            tasks=[content],
            seeds=[0],
            max_steps=5,
            llm=LLMSettings(retry=retry),
        )
    )
    return job


async def until_asked(server: OpenAIServer, requests: int) -> None:
    for _ in range(1200):
        if server.count >= requests:
            return
        await asyncio.sleep(0.05)
    pytest.fail(f"the episodes never made {requests} model requests")


@pytest.mark.slow
async def test_oracle_replays_its_trajectory_and_noop_fails_side_by_side(
    worker: JobWorker, contents: dict[str, TaskContent]
) -> None:

    content = contents["bouncing_ball_stuck"]
    oracle, primitive, noop = await asyncio.gather(
        worker.run(*episode(content)),
        worker.run(*episode(content, mode="primitive")),
        worker.run(*episode(content, agent="noop")),
    )
    trajectory = content.payload.golden_trajectory or []
    assert trajectory, "the task has a golden trajectory"
    assert (oracle.outcome, oracle.stop_reason, oracle.error_class) == ("passed", "done", None)
    assert [step.action for step in oracle.steps] == [action.api for action in trajectory] + ["done"]
    assert [step.args for step in oracle.steps[:-1]] == [action.args for action in trajectory]
    assert all(step.ok for step in oracle.steps)
    assert oracle.steps[0].data == {"editingTarget": "Ball"}  # the envelope's data is kept
    assert oracle.final_project is not None
    assert oracle.final_project[:2] == b"PK"
    assert oracle.evaluation is not None
    assert oracle.evaluation.passed == oracle.evaluation.total >= 3
    assert oracle.worker is not None
    assert oracle.worker.worker_index == 3
    assert 0 < oracle.timings.setup_s < oracle.timings.total_s
    assert oracle.timings.evaluation_s > 0
    assert oracle.finished_at > oracle.started_at > 0

    # In primitive mode the oracle solves it through real gestures only.
    assert primitive.outcome == "passed", primitive.error_message
    assert primitive.steps[-1].action == "done"
    assert {step.action for step in primitive.steps[:-1]} <= set(PRIMITIVE_APIS)
    assert "drag_and_drop" in {step.action for step in primitive.steps}

    assert noop.outcome == "failed"
    assert [step.action for step in noop.steps] == ["done"]
    assert noop.evaluation is not None
    assert noop.evaluation.passed < noop.evaluation.total


async def test_an_episode_past_its_timeout_is_cut_and_leaves_nothing_open(
    worker: JobWorker, contents: dict[str, TaskContent]
) -> None:
    # The browser is up first and the oracle acts by gestures (seconds of them), so the cut lands in the
    # episode on any machine (a slow one once spent the 1.5 s launching the browser).
    assert await worker.warm(1) == await worker.info()  # where it is, for the driver's barrier (_scheduler.py)
    result = await worker.run(*episode(contents["sum_two_numbers"], timeout_s=1.5, mode="primitive"))
    assert (result.outcome, result.error_class, result.stop_reason) == ("error", "episode_timeout", "episode_timeout")
    assert result.error_message == "episode exceeded 1.5 s"
    assert result.timings.total_s >= 1.5  # the cut, not the oracle's end (a lower bound: load only lengthens it)
    assert result.started_at > 0
    session = worker._session
    assert session is not None
    assert session._browser is not None
    # The cancelled episode closed its pages; only evaluation pages waiting for reuse stay open.
    browser = worker._browser
    assert browser is not None and browser.evaluator.pool is not None
    waiting = {editor.page for pages in browser.evaluator.pool._ready.values() for editor in pages}
    assert set(editor_pages(session._browser)) == waiting
    again = await worker.run(*episode(contents["sum_two_numbers"]))
    assert again.outcome == "passed"


@pytest.mark.slow
async def test_a_browser_that_dies_mid_episode_is_an_error_then_replaced(
    worker: JobWorker, contents: dict[str, TaskContent]
) -> None:
    running = asyncio.create_task(worker.run(*episode(contents["sum_two_numbers"])))
    for _ in range(600):
        session = worker._session
        if session is not None and session._browser is not None and editor_pages(session._browser):
            break
        await asyncio.sleep(0.05)
    else:
        pytest.fail("the episode never opened a page")
    first_browser = session._browser
    await first_browser.close()  # as if Chromium crashed
    result = await running
    assert result.outcome == "error", result.model_dump(exclude={"final_project"})
    assert result.error_class == "editor_failure", result.error_message
    again = await worker.run(*episode(contents["sum_two_numbers"]))
    assert again.outcome == "passed"
    assert worker._session is not None
    assert worker._session._browser is not first_browser


@pytest.mark.slow
async def test_a_crashed_page_takes_no_sibling_episode_with_it(
    worker: JobWorker, contents: dict[str, TaskContent], litellm_clients: None, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Two episodes share the worker's browser; one page's renderer dies while both wait on the model."""
    with OpenAIServer(default=reply(DONE_REPLY)) as server:
        job = held_llm_job(server, contents["sum_two_numbers"], monkeypatch)
        payload = contents["sum_two_numbers"].payload
        runs = [asyncio.create_task(worker.run(worker_job(job, attempt, 300), payload)) for attempt in (1, 2)]
        await until_asked(server, 2)  # both agents are waiting for their first reply, each with its own page
        assert worker._session is not None and worker._session._browser is not None
        browser = worker._session._browser
        crashed_page, _ = editor_pages(browser)
        await crash_renderer(crashed_page)
        server.release()
        results = await asyncio.gather(*runs)
    by_outcome = sorted(results, key=lambda r: r.outcome)
    crashed, sibling = by_outcome[0], by_outcome[1]
    assert (crashed.outcome, crashed.error_class) == ("error", "editor_failure"), crashed.error_message
    assert sibling.outcome == "failed", sibling.error_message  # evaluated: "done" without solving
    assert sibling.evaluation is not None and sibling.evaluation.error is None
    assert worker._session is not None and worker._session._browser is browser  # never relaunched
    assert browser.is_connected()


@pytest.mark.slow
async def test_a_browser_that_dies_while_its_episode_waits_on_the_model_ends_it_within_seconds(
    worker: JobWorker, contents: dict[str, TaskContent], litellm_clients: None, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The agent is inside its model call when the browser goes: the episode does not wait for the reply."""
    with OpenAIServer(default=reply(DONE_REPLY)) as server:
        job = held_llm_job(server, contents["sum_two_numbers"], monkeypatch)
        running = asyncio.create_task(worker.run(worker_job(job, 1, 300), contents["sum_two_numbers"].payload))
        await until_asked(server, 1)
        assert worker._session is not None and worker._session._browser is not None
        browser = worker._session._browser
        await browser.close()  # as if Chromium crashed
        result = await running  # the model has not answered, and does not until the end
        server.release()
    assert (result.outcome, result.error_class) == ("error", "editor_failure"), result.error_message
    assert "the browser disconnected" in (result.error_message or "")
    assert worker._session is None  # dropped; the next job starts a new browser


async def test_a_job_planned_for_another_harness_is_refused(contents: dict[str, TaskContent]) -> None:
    worker = JobWorker(worker_index=0, synthetic=SyntheticEpisodes())
    spec, payload = episode(contents["sum_two_numbers"])
    assert (await worker.run(spec, payload)).outcome == "passed"
    foreign = spec.model_copy(update={"harness": "0123456789abcdef"})
    result = await worker.run(foreign, payload)
    assert (result.outcome, result.error_class) == ("error", "harness_mismatch")
    assert "0123456789abcdef" in (result.error_message or "")
    assert kind_fingerprint(harness_fingerprint(), "tasks").digest in (result.error_message or "")
    # Planned under the full fingerprint, or another kind's: refused as well (the digests differ by kind).
    for other in (harness_fingerprint(), kind_fingerprint(harness_fingerprint(), "drag")):
        result = await worker.run(spec.model_copy(update={"harness": other.digest}), payload)
        assert (result.error_class, result.attempt) == ("harness_mismatch", spec.attempt), other.digest


async def test_each_kind_is_checked_against_its_own_fingerprint(contents: dict[str, TaskContent]) -> None:
    """A perception job planned under the perception kind's digest is run (no browser); the tasks digest is refused."""
    worker = JobWorker(worker_index=0)
    screenshot = next((REPO / "perception-items" / "screenshots").glob("*.png")).read_bytes()
    item = PerceptionPayload(
        item_id="vp_1",
        kind="existence",
        tag="existence_yes",
        question="Is a say block visible?",
        answer_format="yes_no",
        answer="YES",
        screenshot_png=screenshot,
    )
    spec = PerceptionSpec(
        job_id="p",
        attempt=1,
        task_id="vp_1",
        agent=AgentRef(name="oracle"),
        model=None,
        seed=0,
        timeout_s=30,
        harness=kind_fingerprint(harness_fingerprint(), "perception").digest,
    )
    result = await worker.run(spec, item)
    assert (result.outcome, result.error_class) == ("passed", None), result.error_message
    refused = await worker.run(spec.model_copy(update={"harness": worker.kind_harness("tasks")}), item)
    assert refused.error_class == "harness_mismatch"
    assert worker.kind_harness("perception") in (refused.error_message or "")
    assert worker._session is None  # neither started a browser


async def test_a_job_no_kind_runs_is_an_internal_error() -> None:
    class UnknownSpec(BaseModel):
        job_id: str = "u"
        attempt: int = 1
        task_id: str = "u"
        timeout_s: float = 5
        harness: str | None = None

    result = await JobWorker(worker_index=0).run(UnknownSpec(), UnknownSpec())  # type: ignore[arg-type]
    assert (result.outcome, result.error_class) == ("error", "internal_error")
    assert "no job kind runs UnknownSpec" in (result.error_message or "")
    assert "drag, perception, tasks" in (result.error_message or "")


async def test_an_unavailable_agent_is_an_agent_error(worker: JobWorker, contents: dict[str, TaskContent]) -> None:
    result = await worker.run(*episode(contents["sum_two_numbers"], agent="llm"))
    assert (result.outcome, result.error_class) == ("error", "agent_error")
    assert "llm" in (result.error_message or "")
    assert worker._session is None  # no browser was started for nothing


class CrashingAgent(AgentBase):
    observes = False
    privileged = True  # it loads projects

    def __init__(self) -> None:
        super().__init__()
        self.calls = 0

    async def act(self, observation: Observation | None, last: StepResult | None) -> Action:
        self.calls += 1
        if self.calls > 1:
            raise RuntimeError("model output could not be parsed")
        return LoadProject(sb3=b"not a zip")


class BusyAgent(AgentBase):
    """Never says done: reloads the project it was given, forever."""

    observes = False
    privileged = True

    def __init__(self, sb3: bytes) -> None:
        super().__init__()
        self.sb3 = sb3

    async def act(self, observation: Observation | None, last: StepResult | None) -> Action:
        return LoadProject(sb3=self.sb3)


async def test_agent_crash_step_limit_and_rejected_actions(
    episode_runner: EpisodeRunner, contents: dict[str, TaskContent]
) -> None:
    runner = episode_runner
    content = contents["sum_two_numbers"]
    spec, payload = episode(content)

    crashed = await runner.run(spec, payload, CrashingAgent())
    assert (crashed.outcome, crashed.error_class) == ("error", "agent_error")
    assert "raised at step 1: RuntimeError: model output could not be parsed" in (crashed.error_message or "")
    rejected, trace = crashed.steps  # the first action was carried out (and refused) before the crash
    assert (rejected.action, rejected.ok, rejected.error_code) == ("load_project", False, "project_invalid")
    assert (trace.action, trace.ok, trace.error_code) == ("agent_error", False, "agent_error")
    assert "Traceback" in (trace.error_message or "") and "in act" in (trace.error_message or "")

    few, _ = episode(content, max_steps=4)  # the limit, not its size, is what ends the episode
    busy = await runner.run(few, payload, BusyAgent(payload.golden_project or b""))
    assert busy.stop_reason == "max_steps"
    assert len(busy.steps) == few.max_steps == 4
    assert all(step.ok for step in busy.steps)
    assert busy.outcome == "passed"  # the step limit ends the episode; the project is still judged


class WaitingAgent(AgentBase):
    """Says done once ``go`` is set: an agent whose model is still thinking until then."""

    observes = False

    def __init__(self, go: asyncio.Event) -> None:
        super().__init__()
        self.go = go
        self.acting = asyncio.Event()

    async def act(self, observation: Observation | None, last: StepResult | None) -> Action:
        self.acting.set()
        await self.go.wait()
        return Done()


SAME_VERDICT = {"timings", "console"}
"""What may differ between two evaluations of one project: how long they took, and the editor's own warnings."""


def threads_by_class(browser_pid: int) -> dict[bool, set[str]]:
    """The threads of a browser's processes but realtime ones (audio), as "process/thread" names,
    by whether they are in the idle class (the names say which thread, should one be in the wrong class)."""
    root = psutil.Process(browser_pid)
    classes: dict[bool, set[str]] = {}
    for process in [root, *root.children(recursive=True)]:
        with contextlib.suppress(psutil.Error):
            for tid, policy in thread_policies(process.pid).items():
                if policy not in {os.SCHED_RR, os.SCHED_FIFO}:
                    classes.setdefault(policy == os.SCHED_IDLE, set()).add(f"{process.name()}/{thread_name(tid)}")
    return classes


def thread_name(tid: int) -> str:
    try:
        return Path(f"/proc/{tid}/comm").read_text().strip()
    except OSError:
        return str(tid)


async def test_a_worker_whose_agents_call_models_starts_its_low_priority_browser_with_its_jobs(
    worker: JobWorker,
) -> None:
    """Warming for jobs that call models opens the agents' editors, and begins starting the idle-class browser
    with its bare evaluation pages (as the first steps wait on the model): started by the first evaluation, once
    agents act, it held up their steps by seconds."""
    await worker.warm(1, calls_models=True)
    browser = worker._browser
    assert browser is not None and browser.background is None  # one page: no other agent to give way to
    await worker.warm(2, calls_models=True)
    assert browser.pool is not None and len(browser.pool._ready["editor"]) == 2
    starting = browser._background_start
    assert starting is not None and browser.start_background() is starting  # begun by warming, and only once
    await starting
    background = browser.background
    assert background is not None and background.pool is not None
    assert len(background.pool._ready["bare"]) == EVALUATIONS_AT_ONCE
    threads = threads_by_class(await background.session.browser_pid())
    assert threads.get(False, set()) == set() and threads[True]  # every thread in the idle class
    assert browser.editors_held == 2 + EVALUATIONS_AT_ONCE


async def test_a_start_of_the_low_priority_browser_cut_short_still_closes_what_it_launched(
    session: BrowserSession,
) -> None:
    """A worker shutting down may cancel the idle-class browser's start midway (launched, its pages opening):
    closing is then no error, and the launched browser is closed, not left behind."""
    browser = WorkerBrowser(session)
    starting = browser.start_background()
    while browser.background is None and not starting.done():  # launched; its bare pages open next, in round trips
        await asyncio.wait([starting], timeout=0.01)
    assert starting.cancel()  # still opening its pages
    background = browser.background
    await browser.close()
    assert starting.cancelled() and browser.background is None
    assert not background.session.connected


async def test_an_evaluation_gives_way_to_episodes_still_acting(
    session: BrowserSession, contents: dict[str, TaskContent]
) -> None:
    """While another episode of the runner acts, a virtual-clock evaluation runs in a browser of the idle class,
    with the verdict it gets at full priority; with no other episode acting, it runs in the runner's own."""
    content = contents["bouncing_ball_stuck"]
    spec, payload = episode(content)
    assert payload.evaluation.clock == "virtual"
    runner = EpisodeRunner(WorkerBrowser(session))
    go = asyncio.Event()
    agent = WaitingAgent(go)
    waiting = asyncio.ensure_future(runner.run(spec, payload, agent))
    try:
        await agent.acting.wait()
        solved = await runner.run(spec, payload, build_agent(spec.agent))
        background = runner.browser.background
        assert background is not None and background.session is not session
        assert solved.outcome == "passed" and solved.evaluation is not None and solved.final_project is not None
        background_pid = await background.session.browser_pid()
        background_threads = threads_by_class(background_pid)
        assert background_threads.get(False, set()) == set() and background_threads[True]
        assert set(threads_by_class(await session.browser_pid())) == {False}
        # An editor opened later is born in the class (the runner moves threads back only after evaluations).
        later = await background.session.open_editor()
        try:
            assert threads_by_class(background_pid).get(False, set()) == set()
        finally:
            await later.close()
        judging = with_random_seed(payload.evaluation, evaluation_seed(spec.task_id, spec.seed))
        at_full_priority = await runner.browser.evaluator.evaluate(solved.final_project, judging)
        assert at_full_priority.model_dump(exclude=SAME_VERDICT) == solved.evaluation.model_dump(exclude=SAME_VERDICT)
        assert background.pool is not None
        opened, reused = background.pool.opened, background.pool.reused
        go.set()
        alone = await waiting
        assert alone.outcome == "failed" and alone.evaluation is not None
        assert (background.pool.opened, background.pool.reused) == (opened, reused)  # evaluated at full priority
    finally:
        go.set()
        await waiting
        await runner.browser.close()
    assert runner.browser.background is None and not background.session.connected
