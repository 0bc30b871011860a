"""Primitive actions on a real editor: every gesture by coordinates and by index, and every refusal."""

from __future__ import annotations

from collections.abc import AsyncIterator
from dataclasses import dataclass

import pytest

from scratchworld_dist.sb3 import Project, block, circle_costume
from tests.conftest import SUITE_DIR, pooled_editor, primitive_editor
from workers.editor import Editor, EditorPool
from workers.primitive import Gestures
from workers.primitive._gestures import GestureError, key_name

pytestmark = pytest.mark.browser

CANVAS = "svg.blocklySvg > .blocklyWorkspace > .blocklyBlockCanvas"
QUIZ = SUITE_DIR / "extend" / "quiz_score" / "initial.sb3"


@dataclass(frozen=True)
class Spot:
    """An element of a hand-made element list: only its centre matters to gestures."""

    x: float
    y: float

    @property
    def center(self) -> tuple[float, float]:
        return self.x, self.y


@pytest.fixture(scope="module")
async def editor(shared_pool: EditorPool) -> AsyncIterator[Editor]:
    async with primitive_editor(shared_pool, QUIZ.read_bytes()) as opened:
        yield opened


@pytest.fixture
def gestures(editor: Editor) -> Gestures:
    return Gestures(editor.page)


async def centre_of(editor: Editor, selector: str, text: str | None = None) -> tuple[float, float]:
    locator = editor.page.locator(selector)
    if text is not None:
        locator = locator.filter(has_text=text)
    box = await locator.first.bounding_box()
    assert box is not None, f"{selector} {text} is not rendered"
    return box["x"] + box["width"] / 2, box["y"] + box["height"] / 2


async def selected_category(editor: Editor) -> str:
    return (await editor.page.locator(".blocklyToolboxCategory.blocklyToolboxSelected").inner_text()).strip()


async def sprite_names(editor: Editor) -> list[str]:
    observation = await editor.call("compositeObserve")
    assert isinstance(observation, dict)
    return [t["name"] for t in observation["targets"] if not t["isStage"]]  # type: ignore[index,union-attr]


async def canvas_transform(editor: Editor) -> str | None:
    return await editor.page.locator(CANVAS).get_attribute("transform")


async def test_click_by_coordinates_and_by_index(editor: Editor, gestures: Gestures) -> None:
    looks = await centre_of(editor, ".blocklyToolboxCategory", "Looks")
    envelope = await gestures.execute("click", {"x": looks[0], "y": looks[1]})
    assert envelope.success, envelope.error
    assert envelope.data == {"x": looks[0], "y": looks[1]}
    assert await selected_category(editor) == "Looks"

    gestures.elements = [Spot(*looks), Spot(*await centre_of(editor, ".blocklyToolboxCategory", "Variables"))]
    assert (await gestures.execute("click", {"index": 1})).success
    assert await selected_category(editor) == "Variables"


async def test_type_key_hotkey_and_double_click_edit_the_sprite_name(editor: Editor, gestures: Gestures) -> None:
    field = await centre_of(editor, "input[class*='sprite-info_sprite-input']")
    assert (await gestures.execute("click", {"x": field[0], "y": field[1]})).success
    assert (await gestures.execute("hotkey", {"keys": ["ctrl", "a"]})).success
    assert (await gestures.execute("type", {"text": "Pilot"})).success
    assert (await gestures.execute("key", {"key": "enter"})).data == {"key": "Enter"}
    assert await sprite_names(editor) == ["Pilot"]

    # A double click selects the word, so typing replaces it.
    assert (await gestures.execute("double_click", {"x": field[0], "y": field[1]})).success
    assert (await gestures.execute("type", {"text": "Quizzer"})).success
    assert (await gestures.execute("hotkey", {"keys": "ctrl+a"})).data == {"keys": ["Control", "a"]}
    assert (await gestures.execute("key", {"key": "Enter"})).success
    assert await sprite_names(editor) == ["Quizzer"]


async def test_scroll_moves_the_workspace(editor: Editor, gestures: Gestures) -> None:
    before = await canvas_transform(editor)
    envelope = await gestures.execute("scroll", {"direction": "down", "amount": 200, "x": 700, "y": 400})
    assert envelope.success, envelope.error
    assert envelope.data == {"dx": 0, "dy": 200}
    moved = await canvas_transform(editor)
    assert moved != before
    gestures.elements = [Spot(700, 400)]
    assert (await gestures.execute("scroll", {"direction": "up", "amount": 200, "index": 0})).success
    assert await canvas_transform(editor) != moved


async def test_drag_moves_a_script_and_right_click_opens_a_menu(editor: Editor, gestures: Gestures) -> None:
    hat = editor.page.locator(f"{CANVAS} > g.blocklyDraggable").first
    before = await hat.get_attribute("transform")
    start = await centre_of(editor, f"{CANVAS} > g.blocklyDraggable > path.blocklyPath")
    envelope = await gestures.execute(
        "drag_and_drop", {"start_x": start[0], "start_y": start[1] - 10, "end_x": start[0] + 60, "end_y": start[1]}
    )
    assert envelope.success, envelope.error
    assert await hat.get_attribute("transform") != before

    gestures.elements = [Spot(start[0] + 60, start[1]), Spot(start[0], start[1] - 10)]
    assert (await gestures.execute("drag_and_drop", {"start_index": 0, "end_index": 1, "duration": 0.2})).success
    assert await hat.get_attribute("transform") == before

    assert (await gestures.execute("click", {"x": 800, "y": 600, "button": "right"})).success
    menu = editor.page.locator(".blocklyContextMenu")
    await menu.wait_for(state="visible")
    assert (await gestures.execute("key", {"key": "esc"})).success
    await menu.wait_for(state="hidden")


@pytest.mark.parametrize(
    ("api", "args", "code", "words"),
    [
        ("click", {"x": 10, "y": 10, "index": 1}, "INVALID_ARG", "not both"),
        ("click", {"x": 10}, "INVALID_ARG", "give x and y, or index"),
        ("click", {"x": 10, "y": 10, "button": "fourth"}, "INVALID_ARG", "button"),
        ("click", {"x": 1280, "y": 10}, "OUT_OF_VIEWPORT", "1280x720"),
        ("double_click", {"x": -1, "y": 10}, "OUT_OF_VIEWPORT", "(-1, 10)"),
        ("click", {"index": 5}, "STALE_INDEX", "not in the latest element list"),
        ("drag_and_drop", {"start_x": 1, "start_y": 1}, "INVALID_ARG", "end_x"),
        ("drag_and_drop", {"start_x": 1, "start_y": 1, "end_x": 2, "end_y": 2, "duration": 60}, "INVALID_ARG", "10"),
        ("scroll", {"direction": "sideways"}, "INVALID_ARG", "direction"),
        ("type", {}, "INVALID_ARG", "text"),
        ("type", {"text": "x", "delay": 5}, "INVALID_ARG", "delay"),
        ("key", {"key": "Hyper"}, "UNKNOWN_KEY", "Hyper"),
        ("hotkey", {"keys": ["ctrl", "Hyper"]}, "UNKNOWN_KEY", "Hyper"),
        ("hotkey", {"keys": []}, "INVALID_ARG", "keys"),
        ("run_js", {"code": "alert(1)"}, "UNKNOWN_API", "drag_and_drop"),
    ],
)
async def test_bad_arguments_are_error_envelopes(
    gestures: Gestures, api: str, args: dict, code: str, words: str
) -> None:
    gestures.elements = [Spot(100, 100)]
    envelope = await gestures.execute(api, args)
    assert not envelope.success
    assert envelope.error is not None
    assert envelope.error.code == code
    assert words in envelope.error.message


async def test_an_index_needs_an_observation_first(gestures: Gestures) -> None:
    envelope = await gestures.execute("click", {"index": 0})
    assert envelope.error is not None
    assert envelope.error.code == "STALE_INDEX"
    assert "no element list" in envelope.error.message


def test_key_names() -> None:
    assert [key_name(k) for k in ("ctrl", "CMD", "left", "Space", "a", "F5", "KeyQ", "PageDown")] == [
        "Control", "Meta", "ArrowLeft", "Space", "a", "F5", "KeyQ", "PageDown",
    ]  # fmt: skip
    with pytest.raises(GestureError, match="unknown key"):
        key_name("F99")


async def test_a_drag_records_whether_it_snapped(shared_pool: EditorPool) -> None:
    """Dropped on empty canvas a block stays alone; dropped under a stack it snaps, and the record says so."""
    project = Project()
    project.sprite("Cat", costume=circle_costume("dot", 10, "#36c")).script(
        block("event_whenflagclicked"), block("looks_say", MESSAGE="hi"), x=40, y=40
    ).script(block("motion_movesteps", STEPS=10), x=40, y=300)
    async with pooled_editor(shared_pool) as editor:
        await editor.load_project(project.to_sb3())
        gestures = Gestures(editor.page, links=lambda: editor.call("primitiveLinks"))

        async def rect(opcode: str) -> dict[str, float]:
            listed = await editor.call("primitiveElements")
            assert isinstance(listed, dict)
            found = [e for e in listed["elements"] if e.get("opcode") == opcode and e.get("where") == "canvas"]  # type: ignore[union-attr]
            assert found, f"{opcode} is not listed on the canvas"
            return found[0]  # type: ignore[no-any-return]

        move = await rect("motion_movesteps")
        away = {"start_x": move["x"] + 8, "start_y": move["y"] + 8, "end_x": move["x"] + 208, "end_y": move["y"] + 8}
        envelope = await gestures.execute("drag_and_drop", away)
        assert envelope.success, envelope.error
        assert envelope.data is not None
        assert envelope.data["snapped"] is False  # type: ignore[index,call-overload]

        move, say = await rect("motion_movesteps"), await rect("looks_say")
        below_say = {
            "start_x": move["x"] + 8,
            "start_y": move["y"] + 8,
            "end_x": say["x"] + 8,
            "end_y": say["y"] + say["height"] + 8,
        }
        envelope = await gestures.execute("drag_and_drop", below_say)
        assert envelope.success, envelope.error
        assert envelope.data is not None
        assert envelope.data["snapped"] is True  # type: ignore[index,call-overload]
        assert envelope.data["attached"] == ["motion_movesteps"]  # type: ignore[index,call-overload]
