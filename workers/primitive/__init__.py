"""Primitive mode: screenshots with an indexed element list, and real mouse and keyboard gestures."""

from workers.primitive._elements import LEGEND, fuse, render, settle
from workers.primitive._gestures import PRIMITIVE_APIS, Gestures
from workers.primitive._observation import PrimitiveObserver, region_ocr
from workers.primitive._pressed_moves import pressed_moves

__all__ = [
    "LEGEND",
    "PRIMITIVE_APIS",
    "Gestures",
    "PrimitiveObserver",
    "fuse",
    "pressed_moves",
    "region_ocr",
    "render",
    "settle",
]
