"""The human agent: a person solves a task in our editor through a live page on 127.0.0.1 (``agent: human``,
``scratchworld play``); their gestures are relayed to the editor and recorded as primitive steps."""

from workers.agents._human._agent import DEFAULT_PORT, PORT_VARIABLE, HumanAgent, HumanParams, human_port
from workers.agents._human._events import Decision, KeyEvent, MouseEvent, WheelEvent
from workers.agents._human._recorder import GestureRecorder

__all__ = [
    "DEFAULT_PORT",
    "PORT_VARIABLE",
    "Decision",
    "GestureRecorder",
    "HumanAgent",
    "HumanParams",
    "KeyEvent",
    "MouseEvent",
    "WheelEvent",
    "human_port",
]
