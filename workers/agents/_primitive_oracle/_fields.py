"""Values through the GUI's widgets: a field's text editor or dropdown, and the GUI's prompts.

Every value is checked where the VM stores it, since a widget may refuse a keystroke or a choice.
"""

from __future__ import annotations

from collections.abc import AsyncIterator
from typing import Literal

from workers.agents._primitive_oracle._colour import pick_colour
from workers.agents._primitive_oracle._divergence import OracleDivergenceError
from workers.agents._primitive_oracle._geometry import FieldGeometry, ModalInput, OpenModal, Point
from workers.agents._primitive_oracle._gestures import click, scroll
from workers.agents._primitive_oracle._page import Page
from workers.agents._primitive_oracle._plan import PlannedStep, Run
from workers.agents._primitive_oracle._scrolling import MAX_SCROLLS, scroll_into_view
from workers.contract import PrimitiveAction

ValueKind = Literal["fields", "inputs"]

VARIABLE_FIELDS = ("VARIABLE", "LIST", "BROADCAST_OPTION")
"""Fields whose dropdown items are names (the VM stores the name, Blockly the id)."""

NEW_MESSAGE = "New message"
TYPE_ATTEMPTS = 3


async def set_block_field(run: Run, step: PlannedStep) -> AsyncIterator[PrimitiveAction]:
    block = run.live_id(step, "blockIndex")
    name = str(step.action.args["fieldName"])
    kind: ValueKind = "fields" if "field" in step.data else "inputs"
    value = str(step.data["value"])
    have = await run.page.block_fields(block)
    if have.values(kind).get(name) == value:
        return
    async for gesture in set_value(run.page, block, name, value, kind, step):
        yield gesture


async def set_value(
    page: Page, block: str, name: str, value: str, kind: ValueKind, step: PlannedStep
) -> AsyncIterator[PrimitiveAction]:
    """Click a field (or an input's value) and type or choose ``value`` as the VM stores it."""
    what = f"{step.describe()}: field {name} of block {block}"

    async def field_points() -> list[Point]:
        _, rect = await page.field(block, name)
        return rect.corners()

    async for gesture in scroll_into_view(page, field_points, what):
        yield gesture
    field, rect = await page.field(block, name)
    yield click(rect.centre())
    if field.kind == "colour":
        async for gesture in pick_colour(page, value, what):
            yield gesture
        async for gesture in close_colour_picker(page, what):
            yield gesture
    elif field.kind == "text":
        async for gesture in focus_text_editor(page, name):
            yield gesture
        async for gesture in type_into_editor(page, value, what):
            yield gesture
        yield PrimitiveAction(api="key", args={"key": "Enter"})
        await page.wait("textEditorClosed", what=f"the text editor of {name} to close")
    else:
        async for gesture in choose(page, field, value, what):
            yield gesture
    await page.wait("quiet", what=f"{name} to settle")
    result = await page.wait_result("blockValue", {"id": block, "kind": kind, "name": name, "value": value})
    if not result.ok:
        raise OracleDivergenceError(f"{what} holds {result.value!r}, not {value!r}")


async def close_colour_picker(page: Page, what: str) -> AsyncIterator[PrimitiveAction]:
    """A click on empty workspace closes the picker, as it closes any dropdown."""
    spot = await page.free_spot(8, 8, None)
    if spot is None:
        raise OracleDivergenceError(f"{what}: no empty workspace to click to close the colour picker")
    yield click(Point(x=spot.x + 4, y=spot.y + 4))
    await page.wait("colourPickerClosed", what="the colour picker to close")


async def focus_text_editor(page: Page, name: str) -> AsyncIterator[PrimitiveAction]:
    """Wait for the text editor a click on field ``name`` opens, and see that it has the keys: an angle
    field opens Scratch's dial beside it, which leaves the editor without focus until it is clicked."""
    await page.wait("textEditorShown", what=f"the text editor of {name}")
    editor = await page.text_editor()
    if not editor.focused and editor.rect is not None:
        yield click(editor.rect.centre())
    await page.wait("textEditorOpen", what=f"the text editor of {name} to take the keys")


async def type_into_editor(page: Page, value: str, what: str) -> AsyncIterator[PrimitiveAction]:
    """Replace the open text editor's text; checked, since a field may refuse a keystroke."""
    seen: list[str | None] = []
    for _ in range(TYPE_ATTEMPTS):
        yield PrimitiveAction(api="hotkey", args={"keys": ["ctrl", "a"]})
        if value:
            yield PrimitiveAction(api="type", args={"text": value})
        else:
            yield PrimitiveAction(api="key", args={"key": "Backspace"})
        editor = await page.text_editor()
        if editor.value == value:
            return
        seen.append(editor.value)
    raise OracleDivergenceError(f"{what}: typing {value!r} left {seen} in the text editor")


async def choose(page: Page, field: FieldGeometry, value: str, what: str) -> AsyncIterator[PrimitiveAction]:
    """Pick ``value`` in the field's open dropdown, scrolling the menu to it (a new message gets a prompt)."""
    await page.wait("menuOpen", what="the dropdown to open")
    if field.name in VARIABLE_FIELDS:
        text = value
    else:
        options = field.options or []
        text = next((o.text for o in options if o.value == value), value)
    for _ in range(MAX_SCROLLS * 3):
        menu = await page.menu()
        items = [item for item in menu.items if item.text == text]
        if not items and field.name == "BROADCAST_OPTION":
            items = [item for item in menu.items if item.text == NEW_MESSAGE]
        if not items:
            offered = [item.text for item in menu.items]
            raise OracleDivergenceError(f"{what}: the dropdown offers no {text!r} (items: {offered})")
        item = items[0]
        if item.visible:
            yield click(item.rect.centre())
            await page.wait("menuClosed", what="the dropdown to close")
            if item.text == NEW_MESSAGE and text != NEW_MESSAGE:
                async for gesture in fill_prompt(page, text):
                    yield gesture
            return
        box = menu.rect
        if box is None:
            raise OracleDivergenceError(f"{what}: the dropdown has no box to scroll")
        delta = item.rect.centre().y - box.centre().y
        yield scroll(delta, 0.0, box.centre())
        await page.wait("menuOpen", what="the dropdown to stop scrolling")
    raise OracleDivergenceError(f"{what}: the dropdown item {text!r} stays out of view")


async def fill_prompt(page: Page, text: str, option: str | None = None) -> AsyncIterator[PrimitiveAction]:
    """Type into the GUI's prompt modal, pick a radio option, press OK."""
    await page.wait("modalOpen", what="the prompt to open")
    modal = await page.modal()
    field = _text_input(modal)
    if not field.focused:
        yield click(field.rect.centre())
    if field.value:
        yield PrimitiveAction(api="hotkey", args={"keys": ["ctrl", "a"]})
    yield PrimitiveAction(api="type", args={"text": text})
    if option is not None:
        modal = await page.modal()
        choices = [o for o in modal.options if o.text == option]
        if not choices:
            offered = [o.text for o in modal.options]
            raise OracleDivergenceError(f"the prompt {modal.title!r} offers no {option!r} (options: {offered})")
        if not choices[0].checked:
            yield click(choices[0].rect.centre())
    modal = await page.modal()
    typed = _text_input(modal).value
    if typed != text:
        raise OracleDivergenceError(f"the prompt {modal.title!r} holds {typed!r}, not {text!r}")
    ok = [b for b in modal.buttons if b.text == "OK"]
    if not ok:
        raise OracleDivergenceError(f"the prompt {modal.title!r} has no OK button")
    yield click(ok[0].rect.centre())
    await page.wait("modalClosed", what="the prompt to close")


def scope_option(scope: str) -> str:
    """The prompt's radio option for a variable's scope (``all``: every sprite)."""
    return "For all sprites" if scope == "all" else "For this sprite only"


def _text_input(modal: OpenModal) -> ModalInput:
    if not modal.inputs:
        raise OracleDivergenceError(f"the prompt {modal.title!r} has no text input")
    return modal.inputs[0]
