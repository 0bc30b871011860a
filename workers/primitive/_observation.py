"""What a primitive-mode agent sees: a screenshot and the indexed element list (DOM fused with OCR).

OCR is the slow part (~0.5 s per full 1280x720 frame on 2 cores), so by default it only reads
the pixels the DOM knows nothing about (the stage, images, paint canvases): the text of blocks
on the workspace comes from their SVG text nodes, which is exact. ``ocr_scope: screen`` reads
the whole frame the way the upstream harness did. Either way, regions that did not change since
an earlier step are served from a cache, and a failing OCR backend degrades to a DOM-only list
with a warning on the step, never silently.
"""

from __future__ import annotations

import asyncio
import base64
import time
from collections.abc import Awaitable
from typing import TypeVar

import cv2
import numpy as np
from playwright.async_api import CDPSession, Page

from workers.contract import ObservationSettings, ObservationTimings, OCRError, PrimitiveObservation
from workers.editor import Editor
from workers.ocr import OCRBackend, Region, RegionOCR, TextBox, ocr_backend
from workers.primitive._elements import fuse, read_dom, render, settle

SETTLE_MAX_MS = 2000
_T = TypeVar("_T")


def region_ocr(settings: ObservationSettings) -> RegionOCR | None:
    """The OCR engine the settings ask for (None: DOM-only lists by choice).

    A backend that cannot start (missing package or model files) still gives an engine: one
    whose every call fails, so each observation degrades to a DOM-only list and says why.
    """
    if settings.ocr == "none":
        return None
    options: dict[str, object] = {"min_score": settings.ocr_min_score}
    if settings.ocr == "paddleocr":
        options |= {"det_model_dir": settings.paddle_det_model_dir, "rec_model_dir": settings.paddle_rec_model_dir}
    try:
        backend: OCRBackend = ocr_backend(settings.ocr, **options)
    except OCRError as exc:
        backend = _UnavailableOCR(settings.ocr, str(exc))
    return RegionOCR(backend)


class _UnavailableOCR:
    """Stands in for a backend that could not start."""

    def __init__(self, name: str, problem: str) -> None:
        self.name = name
        self.problem = problem

    def recognize(self, image: np.ndarray) -> list[TextBox]:
        raise OCRError(self.problem)


class PrimitiveObserver:
    """Makes observations of one page; the OCR engine and its cache may be shared by observers."""

    def __init__(self, settings: ObservationSettings, ocr: RegionOCR | None) -> None:
        self.settings = settings
        self.ocr = ocr
        self._devtools: tuple[Page, CDPSession] | None = None

    async def observe(self, editor: Editor) -> PrimitiveObservation:
        started = time.perf_counter()
        timings = ObservationTimings()
        settled = await settle(editor, SETTLE_MAX_MS)
        timings.settle_ms = _ms_since(started)
        screenshot, dom = await asyncio.gather(_timed(self._screenshot(editor.page)), _timed(read_dom(editor)))
        (png, timings.screenshot_ms), (snapshot, timings.dom_ms) = screenshot, dom
        warnings = [] if settled else [f"the page was still changing after {SETTLE_MAX_MS} ms"]
        ocr_start = time.perf_counter()
        boxes = []
        if self.ocr is not None:
            image = cv2.imdecode(np.frombuffer(png, np.uint8), cv2.IMREAD_COLOR)
            height, width = image.shape[:2]
            if self.settings.ocr_scope == "screen":
                regions = [Region(x=0, y=0, width=width, height=height)]
            else:
                regions = [Region(x=r.x, y=r.y, width=r.width, height=r.height) for r in snapshot.pixel_regions]
            try:
                boxes = await self.ocr.arecognize_regions(image, regions)
            except OCRError as exc:
                warnings.append(f"OCR failed, the element list is DOM-only: {exc}")
        timings.ocr_ms = _ms_since(ocr_start)
        elements = fuse(snapshot, boxes)
        timings.total_ms = _ms_since(started)
        return PrimitiveObservation(
            screenshot_png=png,
            elements=elements,
            text=render(elements),
            settled=settled,
            warnings=warnings,
            timings=timings,
        )

    async def _screenshot(self, page: Page) -> bytes:
        """A PNG of the viewport, taken over the DevTools protocol with ``optimizeForSpeed``.

        Same pixels as ``page.screenshot`` (the text caret is hidden by the page's own style), in
        about half the time: Chromium uses a faster zlib level, the file is ~20% larger.
        """
        if self._devtools is None or self._devtools[0] is not page:
            self._devtools = (page, await page.context.new_cdp_session(page))
        shot = await self._devtools[1].send("Page.captureScreenshot", {"format": "png", "optimizeForSpeed": True})
        return base64.b64decode(shot["data"])


async def _timed(awaitable: Awaitable[_T]) -> tuple[_T, float]:
    started = time.perf_counter()
    return await awaitable, _ms_since(started)


def _ms_since(started: float) -> float:
    return (time.perf_counter() - started) * 1000
