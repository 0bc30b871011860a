"""The indexed element list of primitive mode: what the DOM knows about the page, fused with OCR.

The page (``scratch-gui/primitive/elements.js``) lists what a user can see and point at, the text drawn
in canvas blocks, and the regions where text exists only as pixels. ``fuse`` merges that with
OCR boxes into one list whose indices an agent uses as click targets, and ``render`` turns the
list into prompt text::

    6  blocks  event_whenflagclicked on canvas  (339, 120) 97x49
"""

from __future__ import annotations

import re
import unicodedata
from collections.abc import Sequence
from typing import Literal, Protocol

from pydantic import BaseModel, ConfigDict, Field

from workers.contract import Element, ElementSource
from workers.editor import Editor

BlockWhere = Literal["canvas", "flyout"]

RENDER_TEXT_LIMIT = 100
"""Characters of an element's text shown in a prompt line."""

CONTAIN_TOLERANCE_PX = 2
"""OCR boxes may overhang the element they were read from by this much and still count as inside."""

# Types whose inner text the DOM does not know, so OCR read inside them stays in the list.
_READ_THROUGH_TYPES = frozenset({"canvas", "stage"})

LEGEND = (
    "Element list: one line per element, `index  type  text  (x, y) WxH`, columns separated by two "
    "spaces. (x, y) is the element's top-left corner in screenshot pixels and WxH its size; an action "
    "given an index targets the centre of that element's box. Blocks are named by opcode: "
    '"<opcode> on canvas" is a block in the code area, a bare "<opcode>" is a block in the palette '
    "(flyout). type `text` lines are text read from the screen (blocks' labels and values, OCR of the "
    "stage and pictures)."
)


class _Box(BaseModel):
    model_config = ConfigDict(frozen=True, populate_by_name=True)

    x: int
    y: int
    width: int
    height: int

    def contains(self, other: _Boxlike, tolerance: int = 0) -> bool:
        return (
            other.x >= self.x - tolerance
            and other.y >= self.y - tolerance
            and other.x + other.width <= self.x + self.width + tolerance
            and other.y + other.height <= self.y + self.height + tolerance
        )

    def overlaps(self, other: _Boxlike) -> bool:
        across = min(self.x + self.width, other.x + other.width) - max(self.x, other.x)
        down = min(self.y + self.height, other.y + other.height) - max(self.y, other.y)
        return across > 0 and down > 0


class DomElement(_Box):
    """An element of the page as the DOM pass found it (no index yet)."""

    type: str
    """``menu``, ``tabs``, ``blocks``, ``canvas``, ``sprites``, ``buttons``, ... (see primitive/elements.js)."""

    text: str
    opcode: str | None = None
    """Blocks only: the block's opcode, read through the Blockly API."""

    block_id: str | None = Field(default=None, alias="blockId")
    """Blocks and fields: the id of the block in its workspace."""

    where: BlockWhere | None = None
    """Blocks and fields: on the workspace canvas or in the palette's flyout."""


class DomText(_Box):
    """Text drawn in a canvas block, exactly as the DOM holds it."""

    text: str


class PixelRegion(_Box):
    """A region whose text exists only as pixels: OCR is the only way to read it."""

    kind: Literal["stage", "canvas", "image"]


class DomSnapshot(BaseModel):
    """One synchronous pass over the page."""

    model_config = ConfigDict(frozen=True, populate_by_name=True)

    elements: list[DomElement]
    """Visible, unoccluded elements in DOM order (the flyout's contents top to bottom)."""

    text_boxes: list[DomText] = Field(alias="textBoxes")
    pixel_regions: list[PixelRegion] = Field(alias="pixelRegions")
    elapsed_ms: float = Field(default=0.0, alias="elapsedMs")
    """Time the pass took in the page."""


class _Boxlike(Protocol):
    @property
    def x(self) -> int: ...
    @property
    def y(self) -> int: ...
    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...


class OCRBox(_Boxlike, Protocol):
    """Anything with the attributes of an OCR text box (``workers.ocr.TextBox`` has them)."""

    @property
    def text(self) -> str: ...
    @property
    def score(self) -> float: ...


OCRTuple = tuple[str, float, int, int, int, int]
"""``(text, score, x, y, width, height)``."""


class _Settled(BaseModel):
    settled: bool
    waited_ms: float = Field(alias="waitedMs")


async def read_dom(editor: Editor) -> DomSnapshot:
    """The page's elements, block texts and pixel-only regions, from one pass in the page."""
    return DomSnapshot.model_validate(await editor.call("primitiveElements"))


async def settle(editor: Editor, max_ms: int = 2000) -> bool:
    """Wait until the page holds still (no drag, flyout scroll, bump or DOM change); False on timeout."""
    return _Settled.model_validate(await editor.call("primitiveSettle", {"maxMs": max_ms})).settled


def fuse(dom: DomSnapshot, ocr: Sequence[OCRBox] | Sequence[OCRTuple]) -> list[Element]:
    """The indexed list: DOM elements, then block texts, then the OCR boxes the DOM does not cover.

    An OCR box is dropped when it lies inside a DOM element (whose text the list already has),
    unless that element is the workspace canvas, the stage or a canvas block, whose inner text is
    worth reading, or the box lies inside a pixel-only region; it is also dropped when it repeats
    a DOM text box it overlaps. A block text that only repeats the editable field it sits in is
    left out too.
    """
    entries: list[dict[str, object]] = []
    for element in dom.elements:
        entries.append(
            {
                "type": element.type,
                "text": element.text,
                "x": element.x,
                "y": element.y,
                "width": element.width,
                "height": element.height,
                "opcode": element.opcode,
                "block_id": element.block_id,
            }
        )
    fields = [e for e in dom.elements if e.type == "fields"]
    for box in dom.text_boxes:
        if any(_same_text(box.text, f.text) and f.contains(box, CONTAIN_TOLERANCE_PX) for f in fields):
            continue
        entries.append(_text_entry(box.text, box, "dom"))
    hiding = [e for e in dom.elements if not _reads_through(e)]
    for raw in ocr:
        box = _ocr_box(raw)
        if not _clean(box.text):
            continue
        if any(e.contains(box, CONTAIN_TOLERANCE_PX) for e in hiding) and not any(
            r.contains(box, CONTAIN_TOLERANCE_PX) for r in dom.pixel_regions
        ):
            continue
        if any(_same_text(box.text, t.text) and t.overlaps(box) for t in dom.text_boxes):
            continue
        entries.append(_text_entry(_clean(box.text), box, "ocr"))
    return [Element.model_validate({"index": i, **entry}) for i, entry in enumerate(entries)]


def render(elements: Sequence[Element]) -> str:
    """One ``index  type  text  (x, y) WxH`` line per element (see ``LEGEND``)."""
    return "\n".join(
        f"{e.index}  {e.type}  {_render_text(e.text)}  ({e.x}, {e.y}) {e.width}x{e.height}" for e in elements
    )


class _OCRRect(_Box):
    text: str
    score: float = 1.0


def _ocr_box(raw: OCRBox | OCRTuple) -> _OCRRect:
    if isinstance(raw, tuple):
        text, score, x, y, width, height = raw
    else:
        text, score, x, y, width, height = raw.text, raw.score, raw.x, raw.y, raw.width, raw.height
    return _OCRRect(text=text, score=score, x=round(x), y=round(y), width=round(width), height=round(height))


def _text_entry(text: str, box: _Boxlike, source: ElementSource) -> dict[str, object]:
    return {
        "type": "text",
        "text": text,
        "x": box.x,
        "y": box.y,
        "width": box.width,
        "height": box.height,
        "source": source,
    }


def _reads_through(element: DomElement) -> bool:
    return element.type in _READ_THROUGH_TYPES or (element.type == "blocks" and element.where == "canvas")


_SPACES = re.compile(r"\s+")


def _clean(text: str) -> str:
    """Control and format characters (newlines included) become spaces; runs of space collapse."""
    chars = (" " if unicodedata.category(c) in ("Cc", "Cf", "Zl", "Zp") else c for c in text)
    return _SPACES.sub(" ", "".join(chars)).strip()


def _same_text(a: str, b: str) -> bool:
    return _clean(a).casefold() == _clean(b).casefold()


def _render_text(text: str) -> str:
    cleaned = _clean(text)
    if len(cleaned) > RENDER_TEXT_LIMIT:
        cleaned = cleaned[: RENDER_TEXT_LIMIT - 1].rstrip() + "…"
    return cleaned or '""'
