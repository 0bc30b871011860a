"""The editor bundle's translations are built on first use (``workers/node/_lazy_locales.py``, run by
install.sh): the rewrite, the installed bundle, and a language picked in the editor's own menu."""

from __future__ import annotations

import json
import subprocess

import pytest

from tests.conftest import pooled_editor
from workers.editor import EditorAssets, EditorPool
from workers.node import BUNDLE_FILE
from workers.node._lazy_locales import LazyLocalesError, rewrite

GUI = (
    '"use strict";const i={ab:{"gui.alerts.lostPeripheralConnection":"S {x}","q":"a}b\\"{"},'
    'en:{"gui.x":"X"},"zh-tw":{"gui.y":"\\u4EA4"}};'
)
BLOCKS = (
    'class Ri{static locales={}}Ri.locales.ab={CONTROL_FOREVER:"f}"},Ri.locales.en={CONTROL_FOREVER:"forever"},'
    'Ri.locales["zh-cn"]={CONTROL_FOREVER:"{"};'
)
SNIPPET = GUI + BLOCKS
READ_BACK = """
const built = (target, key) => 'value' in Object.getOwnPropertyDescriptor(target, key);
const before = [built(i, 'ab'), built(Ri.locales, 'zh-cn'), built(i, 'en'), built(Ri.locales, 'en')];
const gui = [i.ab, i.ab === i.ab, Object.keys(i), i['zh-tw']['gui.y'], i.en['gui.x']];
const blocks = [Ri.locales.ab.CONTROL_FOREVER, Ri.locales['zh-cn'].CONTROL_FOREVER, Object.keys(Ri.locales)];
console.log(JSON.stringify({before, gui, blocks, after: [built(i, 'ab'), built(Ri.locales, 'zh-cn')]}));
"""


def node_reads(script: str) -> str:
    return subprocess.run(["node", "-e", script], check=True, capture_output=True, text=True).stdout.strip()


def test_every_language_but_english_is_built_on_first_read_and_then_kept() -> None:
    result = rewrite(SNIPPET)
    assert result.languages == 4 and not result.already
    assert 'en:{"gui.x":"X"}' in result.text and 'Ri.locales.en={CONTROL_FOREVER:"forever"}' in result.text
    assert "get ab(){" in result.text and 'Object.defineProperty(Ri.locales,"zh-cn",{get(){' in result.text
    original = json.loads(node_reads(SNIPPET + READ_BACK))
    lazy = json.loads(node_reads(result.text + READ_BACK))
    assert (lazy["gui"], lazy["blocks"]) == (original["gui"], original["blocks"])
    assert original["before"] == [True] * 4 and lazy["before"] == [False, False, True, True]
    assert lazy["after"] == [True, True]  # read once, each getter has become a plain property


def test_a_rewritten_bundle_is_left_as_it_is() -> None:
    once = rewrite(SNIPPET)
    again = rewrite(once.text)
    assert again.already and again.text == once.text


@pytest.mark.parametrize("broken", [GUI, BLOCKS, "const i={};"])
def test_a_bundle_without_either_message_set_is_refused(broken: str) -> None:
    with pytest.raises(LazyLocalesError, match="translations are not where"):
        rewrite(broken)


def test_a_cut_off_message_set_is_refused() -> None:
    with pytest.raises(LazyLocalesError, match="does not end"):
        rewrite(GUI[: GUI.index("en:")])


def test_the_installed_bundle_builds_its_languages_on_first_use() -> None:
    bundle = EditorAssets().dist_dir / BUNDLE_FILE
    result = rewrite(bundle.read_text(encoding="utf-8"))
    assert result.already, "the editor bundle still builds every language as it starts: run ./install.sh"


@pytest.mark.browser
async def test_a_language_picked_in_the_menu_translates_the_gui_and_the_blocks(shared_pool: EditorPool) -> None:
    async with pooled_editor(shared_pool) as editor:
        page = editor.page
        await page.get_by_text("Settings", exact=True).click()
        await page.get_by_text("Language", exact=True).hover()
        await page.get_by_text("Français", exact=True).click()
        await page.get_by_text("Fichier", exact=True).wait_for()
        blocks = page.locator(".blocklyFlyout .blocklyText")
        await blocks.filter(has_text="arrière-plan suivant").first.wait_for(state="attached")
        palette = await blocks.all_text_contents()
    assert "next backdrop" not in palette
