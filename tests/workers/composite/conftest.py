"""Composite-mode tests' page: a module's pooled editor, the base project loaded with Cat selected (``cat``),
and calls that assert how an API call ended."""

from __future__ import annotations

from collections.abc import AsyncIterator
from typing import Any

import pytest

from scratchworld_dist.sb3 import Project, block, circle_costume
from tests.conftest import pooled_editor
from workers import composite
from workers.contract import ActionEnvelope
from workers.editor import Editor, EditorPool


def base_project() -> Project:
    """Cat: when flag clicked, move 10, turn 15, say "hi"; a forever loop holding one move; a global score."""
    project = Project()
    project.stage.variable("score", 0)
    cat = project.sprite("Cat", costume=circle_costume("cat", 10, "#f80"))
    cat.script(
        block("event_whenflagclicked"),
        block("motion_movesteps", STEPS=10),
        block("motion_turnright", DEGREES=15),
        block("looks_say", MESSAGE="hi"),
    )
    cat.script(block("control_forever", SUBSTACK=[block("motion_changexby", DX=1)]))
    project.sprite("Dog", costume=circle_costume("dog", 10, "#08f"))
    return project


BASE = base_project().to_sb3()


@pytest.fixture(scope="module")
async def editor(shared_pool: EditorPool) -> AsyncIterator[Editor]:
    async with pooled_editor(shared_pool) as page:
        yield page


@pytest.fixture
async def cat(editor: Editor) -> Editor:
    """The base project, freshly loaded, with Cat selected."""
    await editor.load_project(BASE)
    await ok(editor, "select_sprite", name="Cat")
    return editor


async def run(editor: Editor, api: Any, **args: Any) -> ActionEnvelope:
    return await composite.execute(editor, api, args)


async def ok(editor: Editor, api: str, **args: Any) -> Any:
    envelope = await run(editor, api, **args)
    assert envelope.success, envelope.error
    assert envelope.error is None
    return envelope.data


async def fails(editor: Editor, api: Any, code: str, **args: Any) -> str:
    envelope = await run(editor, api, **args)
    assert not envelope.success
    assert envelope.error is not None
    assert envelope.error.code == code, envelope.error
    return envelope.error.message


async def code(editor: Editor) -> str:
    """The pseudocode section of the observation."""
    return (await composite.observe(editor)).text.split("## Blocks Pseudocode\n", 1)[1]


BASE_CAT = """#1 [top] event_whenflagclicked
#2 motion_movesteps
- input STEPS: 10 (math_number)
#3 motion_turnright
- input DEGREES: 15 (math_number)
#4 looks_say
- input MESSAGE: "hi" (text)

#5 [top] control_forever
- SUBSTACK:
  #6 motion_changexby
  - input DX: 1 (math_number)"""
