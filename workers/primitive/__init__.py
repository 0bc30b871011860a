"""Primitive mode: screenshots with an indexed element list, and real mouse and keyboard gestures."""

from workers.primitive._gestures import PRIMITIVE_APIS, Gestures
from workers.primitive._settings import ObservationSettings

__all__ = ["PRIMITIVE_APIS", "Gestures", "ObservationSettings"]
