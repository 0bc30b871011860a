"""The browser session and the editor page: readiness, loud failures, offline, the bridge."""

from __future__ import annotations

import asyncio
import contextlib
import time
from collections.abc import AsyncIterator
from pathlib import Path

import pytest

from scratchworld_dist import (
    BridgeError,
    ChromiumNotFoundError,
    EditorCrashedError,
    EditorNotReadyError,
    RendererUnavailableError,
)
from scratchworld_dist.sb3 import Project, block, check_project, circle_costume
from tests.conftest import copy_page_files, pooled_editor
from tests.support.browser_pages import crash_renderer
from tests.support.projects import counter_project
from workers.contract import EvaluationSpec
from workers.editor import BrowserConfig, BrowserSession, Editor, EditorAssets, EditorPool
from workers.evaluation import Evaluator

pytestmark = pytest.mark.browser


async def test_ready_editor_has_vm_workspace_and_swiftshader(session: BrowserSession) -> None:
    async with session.editor() as editor:
        status = await editor.status()
        assert status.vm and status.workspace and status.project_loads >= 1
        assert status.renderer and "SwiftShader" in (status.renderer_name or "")
        assert status.stage_canvas == (480, 360)
        assert editor.ready_s is not None and editor.ready_s > 0  # measured (bounded by ready_timeout_s)
        assert editor.page.viewport_size == {"width": 1280, "height": 720}


# The test's own probe, not the bridge's: the block types the palette's flyout gains, one list per
# drawing (a drawing is synchronous, so each is one delivery of the observer's records).
FLYOUT_DRAWINGS = """
window.__flyoutDrawings = [];
new MutationObserver((records) => {
  const types = records.flatMap((record) => [...record.addedNodes])
    .filter((node) => node.classList && node.classList.contains('blocklyBlock') && node.closest('.blocklyFlyout'))
    .map((node) => node.classList[0]);
  if (types.length) window.__flyoutDrawings.push(types);
}).observe(document, {subtree: true, childList: true});
"""


@contextlib.asynccontextmanager
async def drawings_counted(*, draw_palette: bool) -> AsyncIterator[Editor]:
    """An editor of a browser of its own whose pages count their palette drawings (``FLYOUT_DRAWINGS``)."""
    async with BrowserSession(BrowserConfig(editor_isolation="origin")) as session:
        assert session._shared is not None
        await session._shared.context.add_init_script(FLYOUT_DRAWINGS)
        editor = await session.open_editor(draw_palette=draw_palette)
        try:
            yield editor
        finally:
            await editor.close()


async def flyout_text(editor: Editor) -> str:
    return (await editor.page.evaluate("document.querySelector('.blocklyFlyout').textContent")).replace("\xa0", " ")


async def test_an_editor_draws_its_palette_once_for_the_default_sprite_before_it_is_ready() -> None:
    # The GUI first draws a stage's palette (no motion blocks), which no one sees; first-palette.js
    # leaves its categories empty, and the editor is ready only once the sprite's palette is drawn.
    async with drawings_counted(draw_palette=True) as editor:
        drawings = await editor.page.evaluate("window.__flyoutDrawings")
    assert len(drawings) == 1, [len(types) for types in drawings]
    assert {"motion_movesteps", "looks_sayforsecs", "event_whenflagclicked"} <= set(drawings[0])


async def test_an_editor_opened_ahead_draws_no_palette_until_its_first_project_draws_its_own() -> None:
    # A pool's editors open without the default project's palette: every use loads a project first, and
    # that load draws the project's own. Recycled, such a page compares clean (what the pool checks).
    async with drawings_counted(draw_palette=False) as editor:
        status = await editor.status()
        assert status.vm and status.project_loads >= 1 and not status.workspace
        assert await editor.page.evaluate("window.__flyoutDrawings") == []

        await editor.load_project(counter_project().to_sb3())
        await editor.page.wait_for_function("() => window.__flyoutDrawings.length > 0", polling=50)
        assert (await editor.status()).workspace
        palette = await flyout_text(editor)
        assert "count" in palette and "my variable" not in palette  # the project's variable, not the default's
        await editor.draw_palette()  # nothing held any more: no second drawing
        drawings = await editor.page.evaluate("window.__flyoutDrawings")
        assert len(drawings) == 1, [len(types) for types in drawings]
        assert {"motion_movesteps", "data_setvariableto"} <= set(drawings[0])
        editor.uses += 1
        assert await editor.recycle() == []


async def test_the_held_palette_of_an_editor_opened_ahead_is_drawn_on_request() -> None:
    async with drawings_counted(draw_palette=False) as editor:
        await editor.draw_palette()
        assert (await editor.status()).workspace
        drawings = await editor.page.evaluate("window.__flyoutDrawings")
        assert len(drawings) == 1
        assert "looks_switchbackdropto" in drawings[0] and "motion_movesteps" not in drawings[0]  # the stage's


async def test_an_editor_opened_ahead_starts_with_an_empty_stage_and_one_opened_for_use_with_the_cat(
    session: BrowserSession,
) -> None:
    # Every use of an editor opened ahead loads a project first: it starts without the default project's
    # sprite (empty-start.js). The default stays for an editor opened for direct use.
    for draw_palette, targets in ((False, ["Stage"]), (True, ["Stage", "Sprite1"])):
        editor = await session.open_editor(draw_palette=draw_palette)
        try:
            project = check_project(await editor.save_project())
            assert [target["name"] for target in project["targets"]] == targets
            assert editor.page_errors == []
        finally:
            await editor.close()


async def test_missing_chromium_is_named(tmp_path: Path) -> None:
    session = BrowserSession(BrowserConfig(executable_path=tmp_path / "chromium"))
    with pytest.raises(ChromiumNotFoundError, match=str(tmp_path / "chromium")):
        await session.start()


async def test_without_webgl_the_editor_fails_loudly() -> None:
    config = BrowserConfig(extra_args=("--disable-software-rasterizer",))
    async with BrowserSession(config) as session:
        with pytest.raises(RendererUnavailableError, match="no WebGL renderer"):
            await session.open_editor()


async def test_a_page_that_never_gets_ready_times_out_with_the_cause(tmp_path: Path) -> None:
    real = EditorAssets()
    copy_page_files(tmp_path)
    # The bridge loads (with the page script it needs at once), the editor bundle never does.
    page = '<!DOCTYPE html><script src="audio.js"></script><script src="bridge.js"></script><p>no editor</p>'
    (tmp_path / "index.html").write_text(page)
    (tmp_path / "node_modules").symlink_to(real.gui_dir / "node_modules")
    config = BrowserConfig(ready_timeout_s=2)
    async with BrowserSession(config, EditorAssets(tmp_path)) as session:
        started = time.monotonic()
        # The configured 2 s, not the default 60, bounded the wait: the timeout's error names the one it had.
        with pytest.raises(
            EditorNotReadyError, match="not ready after 2 s; still missing: VM, rendered workspace, default project"
        ):
            await session.open_editor()
        assert time.monotonic() - started >= 1.9  # it waited for the page first (load only lengthens this)


@pytest.mark.parametrize(
    ("modules", "cause"),
    [
        (
            "{name: 'probe', requires: ['nothing'], create() {}}",
            r"page module nothing \(required by probe\) is not loaded",
        ),
        (
            "{name: 'a', requires: ['b'], create() {}}); scratchworldModule({name: 'b', requires: ['a'], create() {}}",
            "page modules require each other in a cycle",
        ),
    ],
)
async def test_a_page_module_that_cannot_be_created_fails_the_opening_with_the_cause(
    tmp_path: Path, modules: str, cause: str
) -> None:
    real = EditorAssets()
    copy_page_files(tmp_path)
    page = (tmp_path / "index.html").read_text()
    registration = f'<script src="modules.js"></script>\n  <script>scratchworldModule({modules});</script>'
    (tmp_path / "index.html").write_text(page.replace('<script src="modules.js"></script>', registration))
    (tmp_path / "node_modules").symlink_to(real.gui_dir / "node_modules")
    async with BrowserSession(BrowserConfig(ready_timeout_s=3), EditorAssets(tmp_path)) as session:
        with pytest.raises(EditorNotReadyError, match=cause):
            await session.open_editor()


async def test_cdn_requests_fail_at_once_and_do_not_break_the_editor(session: BrowserSession) -> None:
    async with session.editor() as editor:
        failed: list[str] = []
        finished: list[str] = []
        enough = asyncio.Event()

        def on_failed(request) -> None:
            if "cdn.assets.scratch.mit.edu" in request.url:
                failed.append(request.failure or "")
                if len(failed) >= 100:
                    enough.set()

        editor.page.on("requestfailed", on_failed)
        editor.page.on("requestfinished", lambda r: finished.append(r.url) if "scratch.mit.edu" in r.url else None)
        await editor.page.click('button[aria-label="Choose a Sprite"]')  # opens the sprite library
        await asyncio.wait_for(enough.wait(), 120)  # a hang detector: refusals come at once, timeouts never do
        # Refused by the editor server (the page's proxy) at once: none waited out a network timeout.
        assert set(failed) == {"net::ERR_TUNNEL_CONNECTION_FAILED"}
        assert finished == []
        assert "CONNECT cdn.assets.scratch.mit.edu:443" in session.refused_requests
        assert (await editor.status()).vm  # still answering


async def test_load_and_save_round_trip(shared_pool: EditorPool) -> None:
    async with pooled_editor(shared_pool) as editor:
        assert await editor.load_project(counter_project("Counter").to_sb3()) == ["Stage", "Counter"]
        saved = check_project(await editor.save_project())
        assert [t["name"] for t in saved["targets"]] == ["Stage", "Counter"]
        opcodes = {b["opcode"] for b in saved["targets"][1]["blocks"].values() if isinstance(b, dict)}
        assert {"event_whenflagclicked", "control_repeat", "looks_say"} <= opcodes


HOSTILE = [
    "'); window.pwned = true; ('",
    '"; window.pwned = true; "',
    "</script><script>window.pwned = true</script>",
    "${window.pwned = true}",
    "\\'); window.pwned = true; //",
]


async def test_strings_cannot_break_out_of_javascript(evaluator: Evaluator) -> None:
    project = Project()
    for index, name in enumerate(HOSTILE):
        project.sprite(name, costume=circle_costume("c", 5, "#000"), x=index)
    script = (
        "module.exports = async (vm, config) => ({details: [{name: config.label, passed: "
        "typeof window.pwned === 'undefined', meta: {names: vm.runtime.targets.map(t => t.getName())}}]})"
    )
    spec = EvaluationSpec(script_name="x.js", script_source=script, timeout_s=10, config={"label": HOSTILE[0]})
    result = await evaluator.evaluate(project.to_sb3(), spec)
    assert result.error is None, result.error
    assert result.tests[0].name == HOSTILE[0]
    assert result.tests[0].passed  # nothing was executed from the strings
    assert result.tests[0].meta == {"names": ["Stage", *HOSTILE]}


async def test_bridge_rejects_unknown_functions_and_bad_arguments(shared_pool: EditorPool) -> None:
    async with pooled_editor(shared_pool) as editor:
        with pytest.raises(BridgeError) as caught:
            await editor.call("eval", {"code": "1"})
        assert caught.value.kind == "bad_request"
        with pytest.raises(BridgeError) as caught:
            await editor.call("loadProject", {"sb3Base64": 42})
        assert caught.value.kind == "bad_request"


async def test_scripts_cannot_replace_the_bridge(evaluator: Evaluator) -> None:
    script = (
        "module.exports = async () => { try { window.scratchworld = null; } catch (e) {} "
        "return {details: [{name: 'bridge intact', passed: window.scratchworld !== null}]}; }"
    )
    project = Project()
    project.sprite("S", costume=circle_costume("c", 5, "#000")).script(block("event_whenflagclicked"))
    result = await evaluator.evaluate(
        project.to_sb3(), EvaluationSpec(script_name="x.js", script_source=script, timeout_s=10)
    )
    assert result.success, result


async def test_a_crashed_page_is_reported_as_such(session: BrowserSession) -> None:
    async with session.editor() as editor:
        await crash_renderer(editor.page)
        with pytest.raises(EditorCrashedError, match="crashed during status"):
            await editor.status()
    async with session.editor() as editor:  # the browser itself is fine
        assert (await editor.status()).vm
