"""The bare evaluation page (``scratch-gui/bare.html``): what it has, that it gives the editor page's
verdicts, that a script needing the editor goes there, and that a missing install is named."""

from __future__ import annotations

import asyncio
from pathlib import Path

import pytest

from scratchworld_dist.kinds.tasks import read_task
from scratchworld_dist.suites import Task, load_suite
from tests.conftest import REPO, SUITE_DIR, copy_page_files
from tests.support.evaluations import evaluate, spec
from tests.support.retries import SecondLooks
from workers.contract import EditorBundleMissingError, EvalResult, editor_need
from workers.editor import BrowserSession
from workers.editor._server import EditorAssets
from workers.evaluation import Evaluator
from workers.evaluation._profiles import apply_profile

NEEDS_THE_EDITOR = """
module.exports = async (vm) => {
  const workspace = document.querySelector('.blocklyWorkspace');
  return {details: [{name: 'the block workspace is on the page', passed: !!workspace}]};
};
"""

WHAT_THE_PAGE_HAS = """
module.exports = async (vm) => ({details: [
  {name: 'an audio engine', passed: !!vm.runtime.audioEngine && !!vm.runtime.audioEngine.audioContext},
  {name: 'a bitmap adapter', passed: !!vm.runtime.v2BitmapAdapter},
  {name: 'compatibility mode (30 frames a second)', passed: vm.runtime.compatibilityMode === true},
  {name: 'the stage layers', passed: vm.renderer._groupOrdering.length === 4},
]});
"""


Verdicts = tuple[int, int, list[tuple[str, bool]]]


def verdicts(result: EvalResult) -> Verdicts:
    return result.passed, result.total, [(test.name, test.passed) for test in result.tests]


@pytest.mark.browser
async def test_the_bare_page_has_what_verdicts_need_and_the_profiles_stage(session: BrowserSession) -> None:
    async with session.editor("bare") as page:
        status = await page.status()
        assert (status.page, status.vm, status.renderer, status.workspace) == ("bare", True, True, False)
        assert status.audio is not None  # an audio engine: sounds have lengths
        upstream = await apply_profile(page, "upstream")
        assert (upstream.stage_canvas, upstream.mouse_known) == ((240, 180), True)
        native = await apply_profile(page, "native")
        assert native.stage_canvas == (480, 360)


@pytest.mark.browser
async def test_the_page_an_evaluation_ran_in_is_recorded(evaluator: Evaluator) -> None:
    bare = await evaluate(evaluator, WHAT_THE_PAGE_HAS)
    assert bare.success and bare.conditions is not None and bare.conditions.page == "bare", bare
    editor = await evaluate(evaluator, WHAT_THE_PAGE_HAS, page="editor")
    assert editor.success and editor.conditions is not None and editor.conditions.page == "editor", editor


@pytest.mark.browser
async def test_a_script_that_needs_the_editor_runs_there(evaluator: Evaluator) -> None:
    assert spec(NEEDS_THE_EDITOR, page="bare").page == "editor"
    result = await evaluate(evaluator, NEEDS_THE_EDITOR, page="bare")
    assert result.success and result.conditions is not None and result.conditions.page == "editor", result


@pytest.mark.browser
@pytest.mark.slow
@pytest.mark.timeout(1200)  # 24 projects on two pages at once on the real clock: 380 s one page at a time
@pytest.mark.parametrize("clock", ["virtual", "real"])
async def test_our_suite_gets_the_same_verdicts_on_both_pages(
    evaluator: Evaluator, clock: str, second_looks: SecondLooks
) -> None:
    """The virtual clock is deterministic: one pair of evaluations per project, and any difference fails.

    On the real clock a verdict can follow the machine's load (a pacing window missed while other tests run),
    so a difference there gets a second pair, which must agree; every second look is reported in the run's
    summary, and more than one project in eight needing one fails the test (a page that drifts that often
    is not just load)."""

    async def both_pages(task: Task, data: bytes) -> tuple[Verdicts, Verdicts]:
        # At once: a real-clock evaluation mostly waits on the project's own time, and the two pages then
        # share whatever load the machine has.
        bare, editor = await asyncio.gather(
            evaluator.evaluate(data, task.evaluation_spec(clock=clock, page="bare")),  # type: ignore[arg-type]
            evaluator.evaluate(data, task.evaluation_spec(clock=clock, page="editor")),  # type: ignore[arg-type]
        )
        assert bare.error is None and editor.error is None, (task.id, bare.error, editor.error)
        return verdicts(bare), verdicts(editor)

    differences = []
    projects = 0
    for task in load_suite(SUITE_DIR).tasks:
        for project in (task.golden_project, task.initial_project):
            assert project is not None
            projects += 1
            data = project.read_bytes()
            bare, editor = await both_pages(task, data)
            if bare != editor and clock == "real":
                second_looks.took(f"{task.id}/{project.stem}", f"bare {bare} against editor {editor}")
                bare, editor = await both_pages(task, data)
            if bare != editor:
                differences.append((task.id, project.stem, bare, editor))
    assert differences == []
    second_looks.at_most(projects // 8, projects, "projects")


def test_the_page_is_part_of_a_jobs_identity() -> None:
    task = load_suite(SUITE_DIR).tasks[0]
    assert task.evaluation_spec().page == "bare"
    assert read_task(task).task_hash == read_task(task, page="bare").task_hash
    assert read_task(task).task_hash != read_task(task, page="editor").task_hash


def test_scripts_naming_the_editor_are_found_and_ours_name_none() -> None:
    assert editor_need("const w = document.body;") == "document"
    assert editor_need(None, "ScratchBlocks.getMainWorkspace()") == "ScratchBlocks"
    assert editor_need("vm.runtime.targets; // the documented way", "renderer.gl.canvas.width") is None
    assert [task.id for task in load_suite(SUITE_DIR).tasks if task.editor_need() is not None] == []


def test_vendor_files_are_served_from_the_bare_install_only() -> None:
    assets = EditorAssets()
    assert assets.bare_missing is None
    assert assets.resolve("/bare/vendor/scratch-vm/scratch-vm.js") is not None
    assert assets.resolve("/bare/build/scratch-audio.js") is not None
    for refused in ("/bare/vendor/scratch-gui/x.js", "/bare/vendor/scratch-vm/../../package.json", "/bare/stage.jsx"):
        assert assets.resolve(refused) is None, refused


@pytest.mark.browser
async def test_a_checkout_without_the_bare_install_says_so_when_a_bare_page_opens(tmp_path: Path) -> None:
    copy_page_files(tmp_path)
    (tmp_path / "node_modules").symlink_to(REPO / "scratch-gui" / "node_modules")  # the editor only
    assets = EditorAssets(tmp_path)
    assert assets.bare_missing is not None and "run ./install.sh" in assets.bare_missing
    async with BrowserSession(assets=assets) as session:
        with pytest.raises(EditorBundleMissingError, match="bare evaluation page is not installed"):
            await session.open_editor("bare")
