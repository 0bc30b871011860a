"""Primitive mode: screenshots with an indexed element list, and real mouse and keyboard gestures."""

from workers.primitive._elements import LEGEND, Element, fuse, render
from workers.primitive._gestures import PRIMITIVE_APIS, Gestures
from workers.primitive._observation import ObservationTimings, PrimitiveObservation, PrimitiveObserver, region_ocr

__all__ = [
    "LEGEND",
    "PRIMITIVE_APIS",
    "Element",
    "Gestures",
    "ObservationTimings",
    "PrimitiveObservation",
    "PrimitiveObserver",
    "fuse",
    "region_ocr",
    "render",
]
