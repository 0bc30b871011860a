"""``perception validate``: every item of a suite of ours re-derived from its saved project, in this editor.

Each view's saved project is shown again at its view in a clean editor, its facts collected again, and
each item's answer derived again from its ``fact`` by the code that made it (``derive``), its question
written again (``question``: the block reference must still single out its block, the slots and values
still read the same). An item whose answer, question or derivation differs is named. How many pixels of a
new screenshot differ from the stored one is reported per view, for information: the answers rest on the
facts, not on pixels.
"""

from __future__ import annotations

import asyncio
import time
from collections import defaultdict
from collections.abc import Callable, Sequence

from pydantic import BaseModel, ConfigDict

from scratchworld_dist._errors import SuiteError
from scratchworld_dist._files import read_file
from scratchworld_dist.kinds.perception.items._derive import Skip, derive
from scratchworld_dist.kinds.perception.items._facts import ViewFacts
from scratchworld_dist.kinds.perception.items._item import PerceptionItem, PerceptionView
from scratchworld_dist.kinds.perception.items._native import MAX_SCREENSHOT_BYTES, read_screenshot
from scratchworld_dist.kinds.perception.items._page import lending_pool, look, pixel_difference
from scratchworld_dist.kinds.perception.items._questions import question
from scratchworld_dist.kinds.perception.items._suite import PerceptionSuite
from workers.contract import BridgeError, EditorError, ProjectFormatError
from workers.editor import Editor, EditorPool


class ItemCheck(BaseModel):
    model_config = ConfigDict(frozen=True)

    item_id: str
    valid: bool
    problem: str = ""


class ViewCheck(BaseModel):
    """One view's items checked again, and how its new screenshot compares with the stored one."""

    model_config = ConfigDict(frozen=True)

    view: str
    items: list[ItemCheck]
    pixels_differing: float | None
    """Share of the screenshot's pixels that differ from the stored one (None: the view could not be shown)."""

    error: str = ""
    blocks: int = 0
    """Blocks of the target the page measured."""

    facts_ms: float | None = None
    """What measuring them took the page (``perceptionFacts``)."""

    seconds: float

    @property
    def valid(self) -> bool:
        return not self.error and all(item.valid for item in self.items)


def recheck(item: PerceptionItem, facts: ViewFacts) -> str | None:
    """Why ``item`` does not hold in a view with ``facts``, or None when its answer and question are derived again."""
    if item.fact is None:
        return "it names no fact to derive its answer from"
    derived = derive(item.fact, facts)
    if isinstance(derived, Skip):
        return f"its answer cannot be derived: {derived.reason}"
    if derived.answer != item.answer:
        return f"its answer is {item.answer!r} but the view gives {derived.answer!r}"
    if derived.value_kind != item.value_kind:
        return (
            f"it asks for a {item.value_kind or 'YES/NO'} answer but the view gives a {derived.value_kind or 'YES/NO'}"
        )
    written = question(item.fact, facts)
    if written != item.question:
        return f"its question no longer reads as stored (the view words it {written!r})"
    return None


def refuse_upstream(suite: PerceptionSuite) -> None:
    """Only suites we made carry the facts a re-derivation needs."""
    if suite.kind != "scratchworld_dist" or not suite.views:
        raise SuiteError(
            "not a suite made by `scratchworld perception make`: its items carry no facts to re-derive", suite.root
        )


async def validate_perception_suite(
    suite: PerceptionSuite,
    *,
    editors: int = 1,
    views: Sequence[str] | None = None,
    on_checked: Callable[[ViewCheck], None] = lambda _: None,
    pool: EditorPool | None = None,
) -> list[ViewCheck]:
    """Check the items of ``suite`` (of ``views``, default all), view by view in ``editors`` editors at a time
    (from ``pool`` when given, else from a browser of its own)."""
    refuse_upstream(suite)
    by_view: defaultdict[str, list[PerceptionItem]] = defaultdict(list)
    for item in suite.items:
        by_view[item.view or ""].append(item)
    wanted = [view for view in suite.views if views is None or view.id in views]
    queue: asyncio.Queue[int] = asyncio.Queue()
    for index in range(len(wanted)):
        queue.put_nowait(index)
    checks: dict[int, ViewCheck] = {}
    async with lending_pool(pool) as lender:

        async def work() -> None:
            # One editor shows view after view, as `make` shows a target's views: loading a project resets
            # the VM and `show` sets the whole view, so recycling the page between views would only cost time.
            async with lender.editor() as editor:
                while not queue.empty():
                    index = queue.get_nowait()
                    view = wanted[index]
                    checks[index] = await _check_view(editor, view, by_view[view.id])
                    on_checked(checks[index])

        await asyncio.gather(*(work() for _ in range(max(1, editors))))
    return [checks[index] for index in range(len(wanted))]


async def _check_view(editor: Editor, view: PerceptionView, items: list[PerceptionItem]) -> ViewCheck:
    started = time.perf_counter()
    try:
        project = read_file(view.project, MAX_SCREENSHOT_BYTES * 4)
        seen = await look(editor, project, view.view, view.id)
    except (OSError, EditorError, BridgeError, ProjectFormatError) as exc:
        error = f"cannot be shown: {exc}"
        failed = [ItemCheck(item_id=item.id, valid=False, problem=error) for item in items]
        return ViewCheck(view=view.id, items=failed, pixels_differing=None, error=error, seconds=_since(started))
    checked = []
    for item in items:
        problem = recheck(item, seen.facts)
        checked.append(ItemCheck(item_id=item.id, valid=problem is None, problem=problem or ""))
    try:
        difference: float | None = pixel_difference(read_screenshot(view.screenshot), seen.png)
    except SuiteError:
        difference = None
    return ViewCheck(
        view=view.id, items=checked, pixels_differing=difference, blocks=len(seen.facts.blocks),
        facts_ms=seen.facts.ms, seconds=_since(started),
    )  # fmt: skip


def _since(started: float) -> float:
    return time.perf_counter() - started
