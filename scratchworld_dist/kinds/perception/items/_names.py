"""How questions name blocks: a kind by its visible words, a category by its palette name.

A kind's name is the block's English text with its values left out and each dropdown written as a
bracketed placeholder: ``move (10) steps`` is `move steps`, ``set [score v] to (0)`` is
`set [variable] to`. Several opcodes can share a name (the looks and sound ``change [effect] effect
by``), so a name stands for a tuple of opcodes. Blocks whose words are a value (a variable reporter),
My Blocks and extension blocks have no name and are never asked about.
"""

from __future__ import annotations

import re
from collections import defaultdict
from functools import cache
from typing import Literal

from scratchworld_dist.sb3 import SHAPES
from scratchworld_dist.sb3.editing import is_boolean, template_parts, templated_opcodes

Category = Literal[
    "motion", "looks", "sound", "events", "control", "sensing", "operators", "variables", "lists", "myBlocks"
]

ASKED_CATEGORIES: dict[Category, str] = {
    "motion": "Motion",
    "looks": "Looks",
    "sound": "Sound",
    "events": "Events",
    "control": "Control",
    "sensing": "Sensing",
    "operators": "Operators",
    "variables": "Variables",
}
"""The categories a question may name (by the palette's words); lists and My Blocks share colours with them."""

_PREFIXES: dict[str, Category] = {
    "motion": "motion",
    "looks": "looks",
    "sound": "sound",
    "event": "events",
    "control": "control",
    "sensing": "sensing",
    "operator": "operators",
    "procedures": "myBlocks",
    "argument": "myBlocks",
}

_PLACEHOLDERS = {
    "VARIABLE": "variable",
    "LIST": "list",
    "KEY_OPTION": "key",
    "TO": "place",
    "TOWARDS": "place",
    "STYLE": "style",
    "COSTUME": "costume",
    "BACKDROP": "backdrop",
    "EFFECT": "effect",
    "FRONT_BACK": "front or back",
    "FORWARD_BACKWARD": "forward or backward",
    "NUMBER_NAME": "number or name",
    "SOUND_MENU": "sound",
    "WHENGREATERTHANMENU": "measure",
    "BROADCAST_OPTION": "message",
    "BROADCAST_INPUT": "message",
    "STOP_OPTION": "option",
    "CLONE_OPTION": "sprite",
    "TOUCHINGOBJECTMENU": "object",
    "DISTANCETOMENU": "object",
    "DRAG_MODE": "mode",
    "PROPERTY": "property",
    "OBJECT": "sprite",
    "CURRENTMENU": "unit",
    "OPERATOR": "function",
}
"""Our words for what a dropdown chooses, written in brackets in a kind's name."""

HATS = frozenset(
    {
        "event_whenflagclicked", "event_whenkeypressed", "event_whenthisspriteclicked", "event_whenstageclicked",
        "event_whenbackdropswitchesto", "event_whengreaterthan", "event_whenbroadcastreceived",
        "control_start_as_clone",
    }
)  # fmt: skip
"""Blocks that start a script: nothing attaches above them."""

_LOOK_ALIKES: tuple[tuple[str, str], ...] = (
    ("motion_changexby", "motion_setx"), ("motion_changeyby", "motion_sety"), ("motion_changexby", "motion_changeyby"),
    ("motion_setx", "motion_sety"), ("motion_turnright", "motion_turnleft"), ("motion_gotoxy", "motion_glidesecstoxy"),
    ("motion_goto", "motion_glideto"), ("motion_xposition", "motion_yposition"),
    ("motion_pointindirection", "motion_pointtowards"), ("looks_say", "looks_sayforsecs"), ("looks_say", "looks_think"),
    ("looks_sayforsecs", "looks_thinkforsecs"), ("looks_think", "looks_thinkforsecs"), ("looks_show", "looks_hide"),
    ("looks_changesizeby", "looks_setsizeto"), ("looks_nextcostume", "looks_nextbackdrop"),
    ("looks_switchcostumeto", "looks_switchbackdropto"), ("looks_changeeffectby", "looks_seteffectto"),
    ("sound_play", "sound_playuntildone"), ("sound_changevolumeby", "sound_setvolumeto"),
    ("event_broadcast", "event_broadcastandwait"), ("event_whenflagclicked", "event_whenthisspriteclicked"),
    ("event_whenkeypressed", "sensing_keypressed"), ("control_if", "control_if_else"),
    ("control_repeat", "control_repeat_until"), ("control_repeat", "control_forever"),
    ("control_wait", "control_wait_until"),
    ("control_create_clone_of", "control_delete_this_clone"), ("sensing_mousex", "sensing_mousey"),
    ("sensing_touchingobject", "sensing_touchingcolor"), ("sensing_askandwait", "sensing_answer"),
    ("operator_gt", "operator_lt"), ("operator_lt", "operator_equals"), ("operator_gt", "operator_equals"),
    ("operator_add", "operator_subtract"), ("operator_multiply", "operator_divide"), ("operator_and", "operator_or"),
    ("operator_join", "operator_letter_of"), ("operator_round", "operator_mathop"),
    ("data_setvariableto", "data_changevariableby"), ("data_showvariable", "data_hidevariable"),
)  # fmt: skip
"""Kinds that a quick look can take for one another (our choice): absent look-alikes of visible kinds make
the hard existence negatives."""


def category_of(opcode: str) -> Category | None:
    """The palette category whose colour the block has; None for extension blocks."""
    prefix = opcode.split("_", 1)[0]
    if prefix == "data":
        return "lists" if "list" in opcode else "variables"
    return _PREFIXES.get(prefix)


@cache
def kind_name(opcode: str) -> str | None:
    """``opcode``'s name in questions (``set [variable] to``), or None when it is never asked about."""
    category = category_of(opcode)
    if category is None or category == "myBlocks" or opcode in ("data_variable", "data_listcontents"):
        return None
    parts = template_parts(opcode)
    if parts is None:
        return None
    shape = SHAPES.get(opcode)
    words: list[str] = []
    for part in parts:
        if isinstance(part, str):
            words.append(part)
            continue
        bracket, name, _ = part
        slot = shape.inputs.get(name) if shape is not None else None
        menu = name in _PLACEHOLDERS or (shape is not None and name in shape.fields)
        if bracket == "[" and (menu or (slot is not None and slot.kind in ("menu", "broadcast"))):
            words.append(f" [{_PLACEHOLDERS.get(name, name.lower().replace('_', ' '))}] ")
    text = re.sub(r"\s+\?", "?", " ".join("".join(words).split()))
    return text or None


@cache
def _named() -> dict[str, tuple[str, ...]]:
    names: defaultdict[str, list[str]] = defaultdict(list)
    for opcode in templated_opcodes():
        name = kind_name(opcode)
        if name is not None:
            names[name].append(opcode)
    return {name: tuple(sorted(opcodes)) for name, opcodes in names.items()}


def opcodes_named(name: str) -> tuple[str, ...]:
    """Every opcode whose blocks a question names ``name``."""
    return _named().get(name, ())


def all_names() -> tuple[str, ...]:
    """Every kind name, sorted."""
    return tuple(sorted(_named()))


def look_alikes(opcode: str) -> tuple[str, ...]:
    """Kinds (names) that ``opcode``'s blocks can be taken for."""
    found = {b for a, b in _LOOK_ALIKES if a == opcode} | {a for a, b in _LOOK_ALIKES if b == opcode}
    return tuple(sorted({name for other in found if (name := kind_name(other)) is not None}))


def is_boolean_reporter(opcode: str) -> bool:
    """A pointed (hexagonal) reporter: it fits a condition slot."""
    return is_boolean(opcode)
