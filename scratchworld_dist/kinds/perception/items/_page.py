"""A perception view on an editor page: shown, measured (``perceptionFacts``) and photographed.

Both ``perception make`` and ``perception validate`` go through ``look``, so an item is checked against
facts collected exactly as the ones it was made from.
"""

from __future__ import annotations

from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from dataclasses import dataclass

import cv2
import numpy as np

from scratchworld_dist.kinds.perception.items._facts import ViewFacts
from workers.contract import DragView, EditorError
from workers.editor import BrowserConfig, BrowserSession, Editor, EditorPool
from workers.kinds.drag import show, view_held


@dataclass(frozen=True)
class Look:
    facts: ViewFacts
    png: bytes


LOOK_TRIES = 3


async def look(editor: Editor, project: bytes, view: DragView, what: str) -> Look:
    """``project`` in ``view`` (settled), its facts and its screenshot, both of the view as placed: when the
    editor moved the canvas meanwhile, the view is shown again."""
    for _ in range(LOOK_TRIES):
        placed = await show(editor, project, view, what=what)
        facts = ViewFacts.model_validate(await editor.call("perceptionFacts"))
        png = await editor.page.screenshot(type="png")
        if await view_held(editor, placed):
            return Look(facts=facts, png=png)
    raise EditorError(f"{what}: the editor moved the view while it was being measured, {LOOK_TRIES} times")


@asynccontextmanager
async def lending_pool(pool: EditorPool | None) -> AsyncIterator[EditorPool]:
    """``pool`` when given (tests share one browser), else a browser and pool of our own, closed on exit."""
    if pool is not None:
        yield pool
        return
    async with BrowserSession(BrowserConfig()) as session, EditorPool(session, spare=0) as own:
        yield own


def pixel_difference(a: bytes, b: bytes) -> float:
    """The share of pixels that differ between two PNGs (1.0 when their sizes differ)."""
    left = cv2.imdecode(np.frombuffer(a, np.uint8), cv2.IMREAD_COLOR)
    right = cv2.imdecode(np.frombuffer(b, np.uint8), cv2.IMREAD_COLOR)
    if left is None or right is None or left.shape != right.shape:
        return 1.0
    differs = np.any(left != right, axis=2)
    return float(differs.mean())
