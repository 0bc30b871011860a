"""Agent editors are recycled: an episode that leaves every kind of residue is followed by one that
starts as in a fresh editor (same observation, same VM input state, the same picture)."""

from __future__ import annotations

from typing import ClassVar

import cv2
import numpy as np
import pytest
from playwright.async_api import Page

from scratchworld_dist.kinds.tasks import EpisodeMatrix, TaskContent, plan_jobs, read_task
from scratchworld_dist.suites import load_suite
from scratchworld_dist.sweep import worker_job
from tests.conftest import SUITE_DIR
from workers.actor import WorkerBrowser
from workers.agent_api import AgentBase, StepResult, TaskContext, build_agent
from workers.contract import (
    Action,
    AgentRef,
    CompositeObservation,
    Done,
    EpisodeClock,
    Mode,
    Observation,
    ObservationSettings,
)
from workers.editor import BrowserSession, Editor, EditorPool
from workers.kinds.tasks import EpisodeRunner, EpisodeSpec
from workers.primitive._elements import settle

pytestmark = pytest.mark.browser

NO_OCR = ObservationSettings(ocr="none")


@pytest.fixture(scope="module")
def content() -> TaskContent:
    return read_task(load_suite(SUITE_DIR).task("quiz_score"))


def episode(content: TaskContent, mode: Mode) -> EpisodeSpec:
    (job,) = plan_jobs(
        EpisodeMatrix(
            models=[None],
            modes=[mode],
            agent="noop",
            tasks=[content],
            seeds=[0],
            max_steps=5,
            observation=NO_OCR if mode == "primitive" else None,
        )
    )
    return worker_job(job, 1, 120).model_copy(update={"episode_clock": EpisodeClock(mode="virtual")})


class _Privileged(AgentBase):
    privileged: ClassVar[bool] = True

    async def start(self, context: TaskContext) -> None:
        assert context.privileges is not None
        self.editor: Editor = context.privileges.editor


class Messy(_Privileged):
    """Leaves the editor as untidy as an agent can, ending with ``last`` under way."""

    def __init__(self, last: str) -> None:
        super().__init__()
        self.last = last

    async def act(self, observation: Observation | None, last: StepResult | None) -> Action:
        page = self.editor.page
        await _make_a_variable(page, "leftover")  # a variable, its monitor, the palette scrolled
        block = await page.locator(".blocklyFlyout .blocklyDraggable").first.bounding_box()
        assert block is not None
        await _drag(page, block["x"] + 10, block["y"] + 10, 700, 300)  # a block in the workspace
        await page.mouse.move(700, 420)
        await page.mouse.wheel(0, 240)  # the workspace scrolled
        await page.locator(".blocklyZoom > image").first.click()  # and zoomed
        await page.locator('[class*="target-pane_stage-selector"]').click()  # the stage selected
        # A clipped panel scrolled, as a click's scroll-into-view does (seen once in CI, by 2 px).
        await page.locator(".injectionDiv").evaluate("(div) => { div.scrollLeft = 2; }")
        await page.keyboard.down("Shift")
        if self.last == "drag":  # a block held in mid-air
            block = await page.locator(".blocklyFlyout .blocklyDraggable").first.bounding_box()
            assert block is not None
            await page.mouse.move(block["x"] + 10, block["y"] + 10)
            await page.mouse.down()
            for step in range(1, 6):
                await page.mouse.move(block["x"] + 10 + 60 * step, block["y"] + 10 + 20 * step)
        elif self.last == "menu":  # the File menu open
            await page.locator('[class*="menu-bar_menu-bar-item"]', has_text="File").first.click()
        elif self.last == "caret":  # typing into the project title
            await page.locator('[class*="menu-bar_title-field"]').first.click()
            await page.keyboard.type("half")
        elif self.last == "costumes":  # another tab
            await page.locator('[role="tab"]', has_text="Backdrops").first.click()
        return Done()


async def _make_a_variable(page: Page, name: str) -> None:
    await page.locator(".blocklyToolboxCategory, .scratchCategoryMenuItem", has_text="Variables").first.click()
    await page.get_by_text("Make a Variable").first.click()
    await page.locator('[class*="prompt_variable-name-text-input"]').fill(name)
    await page.keyboard.press("Enter")


async def _drag(page: Page, x0: float, y0: float, x1: float, y1: float) -> None:
    await page.mouse.move(x0, y0)
    await page.mouse.down()
    for step in range(1, 11):
        await page.mouse.move(x0 + (x1 - x0) * step / 10, y0 + (y1 - y0) * step / 10)
    await page.mouse.up()


class Observer(_Privileged):
    """Records what the episode's first step shows: the observation, the pixels, the VM's input state."""

    async def act(self, observation: Observation | None, last: StepResult | None) -> Action:
        assert isinstance(observation, CompositeObservation)
        self.text = observation.text
        await settle(self.editor)  # the code area shows the sprite's picture once it has loaded
        await self.editor.page.wait_for_function("() => [...document.images].every((image) => image.complete)")
        self.screenshot = await self.editor.page.screenshot()
        self.status = await self.editor.status()
        self.focused = await self.editor.page.evaluate("() => document.activeElement.tagName")
        return Done()


@pytest.fixture(scope="module")
async def fresh(session: BrowserSession, content: TaskContent) -> Observer:
    observer = Observer()
    result = await EpisodeRunner(WorkerBrowser(session)).run(episode(content, "composite"), content.payload, observer)
    assert result.outcome != "error", result.error_message
    return observer


@pytest.mark.parametrize("last", ["drag", "menu", "caret", "costumes"])
async def test_an_editor_reused_after_an_untidy_episode_starts_the_next_as_a_fresh_one(
    session: BrowserSession, content: TaskContent, fresh: Observer, last: str
) -> None:
    async with EditorPool(session, spare=0) as pool:
        runner = EpisodeRunner(WorkerBrowser(session, pool))
        messy = await runner.run(episode(content, "primitive"), content.payload, Messy(last))
        assert messy.outcome != "error", messy.error_message
        assert messy.steps[-1].action == "done"
        observer = Observer()
        result = await runner.run(episode(content, "composite"), content.payload, observer)
        assert result.outcome != "error", result.error_message
        # One editor served both episodes, one bare page both evaluations.
        assert pool.opened == 2 and pool.reused >= 2, dict(pool.discarded)
    assert observer.text == fresh.text
    # The GUI makes its own AudioContext on a page's first gesture (the messy episode's): it waits suspended
    # as the VM's does (test_page_audio.py), and nothing an agent sees depends on it.
    assert observer.status.model_copy(update={"other_audio": []}) == fresh.status
    assert set(observer.status.other_audio) <= {"suspended"}
    assert observer.focused == fresh.focused
    # The same picture, to the pixel: a leftover menu, tab, zoom, scroll, stage size or held block changes
    # thousands of pixels. With partial raster (Chromium's default), a panel that was scrolled and scrolled
    # back left 35-42 differently anti-aliased pixels on the tabs' rounded corners (measured): see
    # workers/editor/_switches.py.
    assert differing_pixels(observer.screenshot, fresh.screenshot) == 0


def differing_pixels(a: bytes, b: bytes) -> int:
    first = cv2.imdecode(np.frombuffer(a, np.uint8), cv2.IMREAD_COLOR)
    second = cv2.imdecode(np.frombuffer(b, np.uint8), cv2.IMREAD_COLOR)
    assert first.shape == second.shape
    return int(np.any(first != second, axis=2).sum())


@pytest.mark.slow
async def test_the_oracles_episodes_in_both_modes_share_one_editor(session: BrowserSession) -> None:
    """What solving tasks leaves is recycled too: blocks that bound the workspace's scroll, and the
    dropdown Blockly makes anew after the primitive stage is set up (both once closed the editor)."""
    suite = load_suite(SUITE_DIR)
    async with EditorPool(session, spare=0) as pool:
        runner = EpisodeRunner(WorkerBrowser(session, pool))
        for task, mode in (
            ("star_shower", "composite"),
            ("arrow_key_walker", "primitive"),
            ("quiz_score", "composite"),
            ("star_shower", "primitive"),  # reloads its project while page time stands: no bump can be awaited
        ):
            content = read_task(suite.task(task))
            (job,) = plan_jobs(
                EpisodeMatrix(
                    models=[None],
                    modes=[mode],
                    agent="oracle",
                    tasks=[content],
                    seeds=[0],
                    max_steps=300,
                    observation=NO_OCR if mode == "primitive" else None,
                )
            )
            spec = worker_job(job, 1, 300).model_copy(update={"episode_clock": EpisodeClock(mode="virtual")})
            result = await runner.run(spec, content.payload, build_agent(AgentRef(name="oracle")))
            assert result.outcome == "passed", (task, mode, result.error_message)
            assert dict(pool.discarded) == {}, (task, mode)
        assert pool.opened == 2 and pool.reused >= 6  # one editor for the episodes, one bare page for the evaluations
