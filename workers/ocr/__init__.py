"""OCR of editor screenshots behind one interface: rapidocr by default, PaddleOCR as an extra, plus a region cache."""

from workers.contract import OCRError
from workers.ocr._backend import OCRBackend, TextBox
from workers.ocr._factory import ocr_backend
from workers.ocr._paddle import PaddleOCRBackend
from workers.ocr._rapid import RapidOCRBackend
from workers.ocr._regions import Region, RegionOCR

__all__ = [
    "OCRBackend",
    "OCRError",
    "PaddleOCRBackend",
    "RapidOCRBackend",
    "Region",
    "RegionOCR",
    "TextBox",
    "ocr_backend",
]
