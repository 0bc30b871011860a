"""OCR of screen regions with a content cache, so regions unchanged between agent steps are read once."""

from __future__ import annotations

import asyncio
import hashlib
import threading
from collections import OrderedDict
from concurrent.futures import Future

import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from workers.contract import OCRError
from workers.ocr._backend import OCRBackend, TextBox, check_image

_CacheKey = tuple[str, tuple[int, ...], bytes]


class Region(BaseModel):
    """A rectangle to read, in image pixels; it may overhang the image and is clipped to it."""

    model_config = ConfigDict(frozen=True)

    x: int
    """Left edge; negative when the region starts left of the image."""

    y: int
    """Top edge; negative when the region starts above the image."""

    width: int = Field(ge=0)
    """Width in pixels."""

    height: int = Field(ge=0)
    """Height in pixels."""

    @classmethod
    def covering(cls, image: np.ndarray) -> Region:
        """The whole image."""
        return cls(x=0, y=0, width=image.shape[1], height=image.shape[0])


class RegionOCR:
    """Reads regions through a backend, caching results by the region's pixels rather than its position.

    Boxes are stored relative to their crop, so a panel that scrolled or moved but kept its pixels is
    still a hit. Eviction is least-recently-used beyond ``max_entries``. The cache is thread-safe, and a
    read of pixels another thread is reading already waits for that read (``shared``) instead of running
    the backend again: episodes of one task start on the same stage at once, and the stage read cold
    costs about 0.8 CPU-s (rapidocr scales it to 736 pixels on its short side).
    """

    def __init__(self, backend: OCRBackend, max_entries: int = 256) -> None:
        if max_entries < 1:
            raise ValueError(f"max_entries must be at least 1, got {max_entries}")
        self.backend = backend
        self.max_entries = max_entries
        self.hits = 0
        """Regions answered from the cache."""
        self.misses = 0
        """Regions sent to the backend."""
        self.shared = 0
        """Regions answered by a read another thread had already begun (also counted in ``hits``)."""
        self._cache: OrderedDict[_CacheKey, list[TextBox]] = OrderedDict()
        self._reading: dict[_CacheKey, Future[list[TextBox]]] = {}
        self._lock = threading.Lock()

    @property
    def name(self) -> str:
        """The wrapped backend's name, so a ``RegionOCR`` is itself an ``OCRBackend``."""
        return self.backend.name

    def recognize(self, image: np.ndarray) -> list[TextBox]:
        """Read the whole image through the cache."""
        return self.recognize_regions(image, [Region.covering(image)])

    async def arecognize(self, image: np.ndarray) -> list[TextBox]:
        """``recognize`` in a worker thread, so the caller's event loop keeps driving the browser."""
        return await asyncio.to_thread(self.recognize, image)

    def recognize_regions(self, image: np.ndarray, regions: list[Region]) -> list[TextBox]:
        """Read each region (clipped to the image) and return all boxes in image pixels, exact duplicates once."""
        check_image(image)
        height, width = image.shape[:2]
        boxes: dict[TextBox, None] = {}
        for region in regions:
            left, top = max(region.x, 0), max(region.y, 0)
            right, bottom = min(region.x + region.width, width), min(region.y + region.height, height)
            if right <= left or bottom <= top:
                continue
            for box in self._read(image[top:bottom, left:right]):
                boxes[box.model_copy(update={"x": box.x + left, "y": box.y + top})] = None
        return list(boxes)

    async def arecognize_regions(self, image: np.ndarray, regions: list[Region]) -> list[TextBox]:
        """``recognize_regions`` in a worker thread, so the caller's event loop keeps driving the browser."""
        return await asyncio.to_thread(self.recognize_regions, image, regions)

    def _read(self, crop: np.ndarray) -> list[TextBox]:
        """Boxes relative to the crop, from the cache, from a read of the same pixels under way, or the backend."""
        crop = np.ascontiguousarray(crop)
        key = (self.backend.name, crop.shape, hashlib.blake2b(crop.data, digest_size=16).digest())
        with self._lock:
            cached = self._cache.get(key)
            if cached is not None:
                self._cache.move_to_end(key)
                self.hits += 1
                return cached
            reading = self._reading.get(key)
            if reading is None:
                self.misses += 1
                self._reading[key] = mine = Future()
            else:
                self.hits += 1
                self.shared += 1
        if reading is not None:
            return reading.result()  # the reader's boxes, or its OCRError
        try:
            found = self._recognize(crop)
        except BaseException as exc:  # the waiting reads fail too (an interrupted read as an OCRError of theirs)
            with self._lock:
                del self._reading[key]
            interrupted = OCRError(f"the read of these pixels was interrupted ({type(exc).__name__})")
            mine.set_exception(exc if isinstance(exc, Exception) else interrupted)
            raise
        with self._lock:
            del self._reading[key]
            self._cache[key] = found
            self._cache.move_to_end(key)
            while len(self._cache) > self.max_entries:
                self._cache.popitem(last=False)
        mine.set_result(found)
        return found

    def _recognize(self, crop: np.ndarray) -> list[TextBox]:
        """The backend's boxes; any failure of it as an ``OCRError``."""
        try:
            return self.backend.recognize(crop)
        except OCRError:
            raise
        except Exception as exc:
            raise OCRError(f"OCR backend {self.backend.name!r} failed: {type(exc).__name__}: {exc}") from exc
