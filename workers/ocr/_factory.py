"""Backends by name, for settings that name one (``ObservationSettings.ocr``)."""

from __future__ import annotations

from typing import Any

from workers.contract import OCRError
from workers.ocr._backend import OCRBackend
from workers.ocr._paddle import PaddleOCRBackend
from workers.ocr._rapid import RapidOCRBackend

_BACKENDS: dict[str, type[RapidOCRBackend] | type[PaddleOCRBackend]] = {
    RapidOCRBackend.name: RapidOCRBackend,
    PaddleOCRBackend.name: PaddleOCRBackend,
}


def ocr_backend(name: str = RapidOCRBackend.name, **options: Any) -> OCRBackend:
    """Create the backend called ``name`` with its constructor ``options``; neither imports an engine yet."""
    backend = _BACKENDS.get(name)
    if backend is None:
        raise OCRError(f"no OCR backend {name!r}; choose one of: {', '.join(_BACKENDS)}")
    return backend(**options)
