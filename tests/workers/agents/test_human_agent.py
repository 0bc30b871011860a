"""The human agent with Playwright as the person, through the page it serves: the primitive oracle's golden
gestures, made on that page's live picture of the editor, solve a task of our suite and are recorded as the
oracle's steps; Give up fails the task; a page closed for good is an error a resume runs again."""

from __future__ import annotations

import asyncio
import contextlib
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from dataclasses import dataclass
from pathlib import Path

import pytest
from playwright.async_api import Browser, Page, async_playwright, expect

from scratchworld_dist.kinds.tasks import EpisodeMatrix, TaskContent, plan_jobs, read_task
from scratchworld_dist.results import RunStore, record_of
from scratchworld_dist.suites import load_suite
from scratchworld_dist.sweep import JobSpec, worker_job
from tests.conftest import SUITE_DIR, primitive_editor
from tests.support.primitive_oracle import drive
from workers.agents._human import HumanAgent
from workers.agents._primitive_oracle import PrimitiveOracle
from workers.contract import (
    PERMANENT_ERRORS,
    AgentRef,
    EpisodeClock,
    JobResult,
    Mode,
    ObservationSettings,
    PrimitiveAction,
)
from workers.editor import BrowserConfig, EditorPool
from workers.kinds.tasks import EpisodeRunner, EpisodeSpec
from workers.primitive._gestures import key_name

pytestmark = pytest.mark.browser

SOLVED_TASK = "bouncing_ball_stuck"
"""A debug task of our suite whose golden gestures are four drags (the stage's clicks and a dropdown's, in
traffic_light_skips_yellow, pass the same way: left out for time)."""


def task(task_id: str) -> TaskContent:
    return read_task(load_suite(SUITE_DIR).task(task_id))


def planned(content: TaskContent, mode: Mode = "primitive") -> JobSpec:
    (job,) = plan_jobs(
        EpisodeMatrix(
            models=[None],
            modes=[mode],
            agent=AgentRef(name="human", params={"participant": "tester"}),
            tasks=[content],
            seeds=[0],
            max_steps=50,
            episode_clock=EpisodeClock(mode="real"),
            observation=ObservationSettings(ocr="none"),  # DOM-only element lists: what a person sees is the page
        )
    )
    return job


def episode(content: TaskContent, attempt: int = 1, mode: Mode = "primitive") -> EpisodeSpec:
    return worker_job(planned(content, mode), attempt, 120)  # type: ignore[return-value]


@pytest.fixture(scope="module")
async def person_browser() -> AsyncIterator[Browser]:
    """The person's own browser: a plain Chromium (the editor's is confined to the editor's origins)."""
    async with async_playwright() as playwright:
        browser = await playwright.chromium.launch(executable_path=str(BrowserConfig().executable_path))
        yield browser
        await browser.close()


@dataclass
class Person:
    """Playwright at the human page: gestures aimed at the editor's picture, in the editor's pixels."""

    page: Page
    episode: asyncio.Task[JobResult]

    async def ready(self, steps: int) -> None:
        """Wait until the harness recorded ``steps`` steps and observed the editor for the next one (an episode
        that ends meanwhile fails the test with its result)."""
        shown = asyncio.ensure_future(
            self.page.wait_for_function(
                "n => document.body.dataset.ready === 'true' && Number(document.body.dataset.steps) === n", arg=steps
            )
        )
        await asyncio.wait([shown, self.episode], return_when=asyncio.FIRST_COMPLETED)
        if not shown.done():
            shown.cancel()
            raise AssertionError(f"the episode ended before step {steps}: {self.episode.result()}")
        await shown

    async def at(self, x: float, y: float) -> tuple[float, float]:
        box = await self.page.locator("#frame").bounding_box()
        assert box is not None
        return box["x"] + x * box["width"] / 1280, box["y"] + y * box["height"] / 720

    async def perform(self, action: PrimitiveAction) -> None:
        mouse, keyboard, args = self.page.mouse, self.page.keyboard, action.args
        if action.api in ("click", "double_click"):
            x, y = await self.at(float(args["x"]), float(args["y"]))  # type: ignore[arg-type]
            await (mouse.click(x, y) if action.api == "click" else mouse.dblclick(x, y))
        elif action.api == "drag_and_drop":
            start = await self.at(float(args["start_x"]), float(args["start_y"]))  # type: ignore[arg-type]
            end = await self.at(float(args["end_x"]), float(args["end_y"]))  # type: ignore[arg-type]
            await mouse.move(*start)
            await mouse.down()
            await mouse.move(*end, steps=15)
            await mouse.up()
        elif action.api == "scroll":
            await mouse.move(*await self.at(float(args["x"]), float(args["y"])))  # type: ignore[arg-type]
            amount = float(args.get("amount", 100))  # type: ignore[arg-type]
            sign = -1 if args["direction"] in ("up", "left") else 1
            vertical = args["direction"] in ("up", "down")
            await mouse.wheel(0 if vertical else sign * amount, sign * amount if vertical else 0)
        elif action.api == "type":
            await keyboard.type(str(args["text"]))
        elif action.api == "key":
            await keyboard.press(key_name(str(args["key"])))
        elif action.api == "hotkey":
            await keyboard.press("+".join(key_name(str(key)) for key in args["keys"]))  # type: ignore[union-attr]
        else:
            raise AssertionError(f"no way to act out {action.api}")


@asynccontextmanager
async def playing(
    runner: EpisodeRunner,
    content: TaskContent,
    browser: Browser,
    agent: HumanAgent | None = None,
    attempt: int = 1,
    mode: Mode = "primitive",
) -> AsyncIterator[tuple[Person, asyncio.Task[JobResult]]]:
    """The episode running (as attempt ``attempt``), and the person at its page once it is served."""
    agent = agent or HumanAgent(HumanAgent.Params(participant="tester"))
    agent.port = 0  # any free port: tests run side by side
    running = asyncio.ensure_future(runner.run(episode(content, attempt, mode), content.payload, agent))
    opened = asyncio.ensure_future(agent.opened.wait())
    await asyncio.wait([running, opened], return_when=asyncio.FIRST_COMPLETED)
    if running.done():
        opened.cancel()
        raise AssertionError(f"the episode ended before its page was served: {running.result()}")
    assert agent.server is not None
    context = await browser.new_context(viewport={"width": 1600, "height": 800})
    page = await context.new_page()
    await page.goto(agent.server.url)
    try:
        yield Person(page, running), running
    finally:
        await context.close()
        if not running.done():  # a failed test: the episode ends now, its page server closed, nothing left open
            running.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await running


async def oracle_gestures(pool: EditorPool, content: TaskContent) -> list[PrimitiveAction]:
    """What the primitive oracle does on the task's initial project, gesture by gesture."""
    initial = content.payload.initial_project
    async with primitive_editor(pool, initial) as editor:
        oracle = PrimitiveOracle(initial, content.payload.golden_trajectory or [])
        await oracle.begin(editor)
        return (await drive(editor, oracle)).actions


@pytest.mark.slow
async def test_the_oracles_gestures_made_through_the_page_solve_the_task_and_are_its_steps(
    episode_runner: EpisodeRunner, shared_pool: EditorPool, person_browser: Browser
) -> None:
    task_id = SOLVED_TASK
    content = task(task_id)
    gestures = await oracle_gestures(shared_pool, content)
    assert gestures
    async with playing(episode_runner, content, person_browser) as (person, running):
        await person.page.wait_for_function("document.body.dataset.frames === 'yes'")  # the editor, live
        title = await person.page.locator("#title").text_content()
        assert title == f"{task_id} (primitive), tester"
        assert await person.page.locator("#instruction").text_content() == content.payload.instruction
        for done, gesture in enumerate(gestures):
            await person.ready(done)
            await person.perform(gesture)
        await person.ready(len(gestures))
        await person.page.click("#submit")
        result = await running
        await person.page.wait_for_function("document.body.dataset.ended === 'done'")
    assert (result.outcome, result.stop_reason) == ("passed", "done"), result.error_message
    *steps, done = result.steps
    assert done.action == "done"
    assert [step.action for step in steps] == [gesture.api for gesture in gestures]
    for step, gesture in zip(steps, gestures, strict=True):
        assert step.ok
        assert step.episode_clock_ms is None  # the wall clock
        assert step.observation is not None
        assert step.observation.screenshot in result.images  # what the editor showed before the step
        if gesture.api == "drag_and_drop":
            for key in ("start_x", "start_y", "end_x", "end_y"):
                assert step.args[key] == pytest.approx(gesture.args[key], abs=1.0)
        else:
            assert {k: v for k, v in step.args.items() if k in gesture.args} == pytest.approx(gesture.args, abs=1.0)


@pytest.mark.parametrize("mode", ["primitive", "composite"])
async def test_giving_up_fails_the_task(episode_runner: EpisodeRunner, person_browser: Browser, mode: Mode) -> None:
    """In either mode: the person works in the GUI, and their steps are gestures (the mode chooses what is
    observed between them: a screenshot and element list, or the composite text)."""
    content = task(SOLVED_TASK)
    async with playing(episode_runner, content, person_browser, mode=mode) as (person, running):
        # The title comes once the page has its task from the server (seen under a full suite's load: not yet).
        await expect(person.page.locator("#title")).to_have_text(f"{SOLVED_TASK} ({mode}), tester", timeout=60_000)
        await person.ready(0)
        x, y = await person.at(640, 400)
        await person.page.mouse.click(x, y)  # a click on the workspace: one step
        await person.ready(1)
        await person.page.click("#give-up")
        result = await running
        await person.page.wait_for_function("document.body.dataset.ended === 'failed'")
    assert (result.outcome, result.stop_reason) == ("failed", "failed")
    click, failed = result.steps
    assert (click.action, click.args, click.ok) == ("click", {"x": 640.0, "y": 400.0}, True)
    assert click.observation is not None
    assert (click.observation.screenshot is not None) == (mode == "primitive")
    assert (click.observation.text is not None) == (mode == "composite")
    assert failed.action == "failed"
    assert result.evaluation is not None
    assert not result.evaluation.success


async def test_a_page_closed_for_good_is_an_error_that_resumes(
    episode_runner: EpisodeRunner, person_browser: Browser, tmp_path: Path
) -> None:
    content = task(SOLVED_TASK)
    agent = HumanAgent(HumanAgent.Params(participant="tester"))
    agent.reconnect_grace_s = 0.5
    async with playing(episode_runner, content, person_browser, agent) as (person, running):
        await person.ready(0)
        await person.page.keyboard.press("ArrowRight")  # keys go to the editor while its picture has the focus
        await person.ready(1)
        await person.page.close()
        result = await running
    assert (result.outcome, result.error_class) == ("error", "participant_left")
    assert "closed" in (result.error_message or "")
    assert result.error_class not in PERMANENT_ERRORS  # retried within the run
    key, left = result.steps
    assert (key.action, key.args) == ("key", {"key": "ArrowRight"})
    assert left.error_code == "participant_left"
    # A resume runs the job again, as its next attempt; the person's verdict then decides it.
    job, store = planned(content), RunStore(tmp_path / "run")
    store.open_for_writing()
    store.commit(record_of(job, result, run_name="human", suite_hash="suite", artifact_dir=None))
    assert store.undecided([job]) == [(job, 2)]
    async with playing(episode_runner, content, person_browser, attempt=2) as (person, running):
        await person.ready(0)
        await person.page.click("#give-up")
        again = await running
    assert (again.attempt, again.outcome) == (2, "failed")
    store.commit(record_of(job, again, run_name="human", suite_hash="suite", artifact_dir=None))
    assert store.undecided([job]) == []
    store.close()
