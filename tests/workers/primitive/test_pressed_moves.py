"""A drag's moves past Chromium's HTML5-drag decision go to the page directly: the page sees the same
pointer events, and a drag that does start an HTML5 drag stays Playwright's to carry on."""

from __future__ import annotations

from collections.abc import Awaitable, Callable
from typing import Any

import pytest
from playwright.async_api import Page

from tests.conftest import SUITE_DIR, primitive_editor
from workers.contract import EpisodeClock
from workers.editor import Editor, EditorPool
from workers.kinds.drag import _page as drag_page
from workers.kinds.tasks._pace import Pace
from workers.primitive import Gestures
from workers.primitive._pressed_moves import PressedMoves, decided, html5_dragging

QUIZ = SUITE_DIR / "extend" / "quiz_score" / "initial.sb3"
PALETTE_TO_CANVAS = {"start_x": 60, "start_y": 250, "end_x": 500, "end_y": 300}
"""A palette block dragged into the code area: 15 moves of 29 px, the first past the decision."""

RECORD_POINTER_MOVES = """() => {
  const moves = [];
  const record = (e) => { if (e.isTrusted) moves.push([e.clientX, e.clientY, e.buttons, e.pressure, e.pointerType]); };
  window.addEventListener('pointermove', record, true);
  window.__takeMoves = () => {
    window.removeEventListener('pointermove', record, true);
    delete window.__takeMoves;
    return moves;
  };
}"""
HTML5_SOURCE_AND_TARGET = """() => {
  const box = (left, draggable) => {
    const el = document.createElement('div');
    el.className = 'pressed-moves-test';
    el.style.cssText = `position:fixed;left:${left}px;top:300px;width:60px;height:60px;z-index:99999;background:#c33`;
    if (draggable) el.draggable = true;
    document.body.appendChild(el);
    return el;
  };
  window.__dragEvents = [];
  const source = box(200, true), target = box(600, false);
  source.addEventListener('dragstart', (e) => {
    e.dataTransfer.setData('text/plain', 'x');
    window.__dragEvents.push('dragstart');
  });
  target.addEventListener('dragover', (e) => { e.preventDefault(); });
  target.addEventListener('drop', (e) => { e.preventDefault(); window.__dragEvents.push('drop'); });
  source.addEventListener('dragend', () => window.__dragEvents.push('dragend'));
}"""
REMOVE_TEST_BOXES = "() => document.querySelectorAll('.pressed-moves-test').forEach((el) => el.remove())"


def test_the_decision_is_past_twice_the_threshold_in_either_axis() -> None:
    assert not decided((100, 100), (107.9, 92.1))
    assert decided((100, 100), (108, 100))
    assert decided((100, 100), (100, 92))


@pytest.mark.parametrize(
    ("reply", "dragging"),
    [({"dragging": False}, False), ({"dragging": True}, True), ({}, True), (None, True), ({"dragging": 0}, True)],
)
def test_only_a_plain_no_lets_moves_go_direct(reply: Any, dragging: bool) -> None:
    assert html5_dragging(reply) is dragging


def counting_direct_moves(monkeypatch: pytest.MonkeyPatch) -> list[tuple[float, float]]:
    """The points ``PressedMoves.move`` sends (it still sends them)."""
    sent: list[tuple[float, float]] = []
    real = PressedMoves.move

    async def move(self: PressedMoves, x: float, y: float) -> None:
        sent.append((x, y))
        await real(self, x, y)

    monkeypatch.setattr(PressedMoves, "move", move)
    return sent


async def drag_on_the_virtual_clock(
    editor: Editor, args: dict[str, Any], dragging: Callable[[], Awaitable[Any]] | None
) -> None:
    pace = Pace(editor, EpisodeClock(mode="virtual"))
    await pace.start()
    envelope = await Gestures(editor.page, pace.pass_time, dragging=dragging).execute("drag_and_drop", args)
    assert envelope.success, envelope.error


async def pointer_moves(page: Page) -> list[list[Any]]:
    moves = await page.evaluate("() => window.__takeMoves()")
    assert isinstance(moves, list)
    return moves


@pytest.mark.browser
async def test_direct_moves_are_the_pointer_events_playwright_would_make(
    shared_pool: EditorPool, monkeypatch: pytest.MonkeyPatch
) -> None:
    sent = counting_direct_moves(monkeypatch)
    seen = []
    for direct in (False, True):
        async with primitive_editor(shared_pool, QUIZ.read_bytes()) as editor:
            await editor.page.evaluate(RECORD_POINTER_MOVES)
            dragging = (lambda: editor.call("primitiveDragging")) if direct else None
            await drag_on_the_virtual_clock(editor, PALETTE_TO_CANVAS, dragging)
            seen.append(await pointer_moves(editor.page))
    assert len(sent) == 13  # the first move decides, the last goes through Playwright's mouse again
    assert seen[0] == seen[1]
    assert len(seen[1]) == 16 and all(move[2:] == [1, 0.5, "mouse"] for move in seen[1][1:])


@pytest.mark.browser
async def test_the_drag_benchmarks_drags_go_direct_too(
    shared_pool: EditorPool, monkeypatch: pytest.MonkeyPatch
) -> None:
    sent = counting_direct_moves(monkeypatch)
    async with primitive_editor(shared_pool, QUIZ.read_bytes()) as editor:
        await editor.page.evaluate(RECORD_POINTER_MOVES)
        await drag_page.drag(editor, (60, 250), (500, 300))
        moves = await pointer_moves(editor.page)
    steps = drag_page.DRAG_STEPS
    assert len(sent) == steps - 2  # the first move decides, the last goes through Playwright's mouse again
    along = [coord for step in range(1, steps + 1) for coord in (60 + 440 * step / steps, 250 + 50 * step / steps)]
    seen = [coord for move in moves[-steps:] for coord in move[:2]]
    assert seen == pytest.approx(along, abs=0.01)
    assert all(move[2:] == [1, 0.5, "mouse"] for move in moves[-steps:])


@pytest.mark.browser
async def test_an_html5_drag_stays_playwrights_to_carry_on(
    shared_pool: EditorPool, monkeypatch: pytest.MonkeyPatch
) -> None:
    sent = counting_direct_moves(monkeypatch)
    async with primitive_editor(shared_pool, QUIZ.read_bytes()) as editor:
        await editor.page.evaluate(HTML5_SOURCE_AND_TARGET)
        try:
            across = {"start_x": 230, "start_y": 330, "end_x": 630, "end_y": 330}
            await drag_on_the_virtual_clock(editor, across, lambda: editor.call("primitiveDragging"))
            events = await editor.page.evaluate("() => window.__dragEvents")
        finally:
            await editor.page.evaluate(REMOVE_TEST_BOXES)
    assert sent == []
    assert events == ["dragstart", "drop", "dragend"]
