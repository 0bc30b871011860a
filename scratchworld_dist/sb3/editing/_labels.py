"""Blocks named as the editor shows them, "move (10) steps": drag instructions and perception questions.

A model sees a screenshot, not ids, so an instruction or a question names blocks by their visible text: an
English template per Scratch 3 block, filled from the project's own inputs and fields (or with
the palette's defaults for a block still in the flyout). Templates mark slots as ``(NAME=default)``
(round), ``[NAME=default]`` (square: text, menus, fields) and ``<NAME>`` (hexagonal: booleans).
"""

from __future__ import annotations

import json
import re
from collections.abc import Mapping
from typing import Any

_TEMPLATES: dict[str, str] = {
    "motion_movesteps": "move (STEPS=10) steps",
    "motion_turnright": "turn right (DEGREES=15) degrees",
    "motion_turnleft": "turn left (DEGREES=15) degrees",
    "motion_goto": "go to [TO=random position]",
    "motion_gotoxy": "go to x: (X=0) y: (Y=0)",
    "motion_glideto": "glide (SECS=1) secs to [TO=random position]",
    "motion_glidesecstoxy": "glide (SECS=1) secs to x: (X=0) y: (Y=0)",
    "motion_pointindirection": "point in direction (DIRECTION=90)",
    "motion_pointtowards": "point towards [TOWARDS=mouse-pointer]",
    "motion_changexby": "change x by (DX=10)",
    "motion_setx": "set x to (X=0)",
    "motion_changeyby": "change y by (DY=10)",
    "motion_sety": "set y to (Y=0)",
    "motion_ifonedgebounce": "if on edge, bounce",
    "motion_setrotationstyle": "set rotation style [STYLE=left-right]",
    "motion_xposition": "x position",
    "motion_yposition": "y position",
    "motion_direction": "direction",
    "looks_sayforsecs": "say [MESSAGE=Hello!] for (SECS=2) seconds",
    "looks_say": "say [MESSAGE=Hello!]",
    "looks_thinkforsecs": "think [MESSAGE=Hmm...] for (SECS=2) seconds",
    "looks_think": "think [MESSAGE=Hmm...]",
    "looks_switchcostumeto": "switch costume to [COSTUME]",
    "looks_nextcostume": "next costume",
    "looks_switchbackdropto": "switch backdrop to [BACKDROP]",
    "looks_switchbackdroptoandwait": "switch backdrop to [BACKDROP] and wait",
    "looks_nextbackdrop": "next backdrop",
    "looks_changesizeby": "change size by (CHANGE=10)",
    "looks_setsizeto": "set size to (SIZE=100) %",
    "looks_changeeffectby": "change [EFFECT=color] effect by (CHANGE=25)",
    "looks_seteffectto": "set [EFFECT=color] effect to (VALUE=0)",
    "looks_cleargraphiceffects": "clear graphic effects",
    "looks_show": "show",
    "looks_hide": "hide",
    "looks_gotofrontback": "go to [FRONT_BACK=front] layer",
    "looks_goforwardbackwardlayers": "go [FORWARD_BACKWARD=forward] (NUM=1) layers",
    "looks_costumenumbername": "costume [NUMBER_NAME=number]",
    "looks_backdropnumbername": "backdrop [NUMBER_NAME=number]",
    "looks_size": "size",
    "sound_playuntildone": "play sound [SOUND_MENU] until done",
    "sound_play": "start sound [SOUND_MENU]",
    "sound_stopallsounds": "stop all sounds",
    "sound_changeeffectby": "change [EFFECT=pitch] effect by (VALUE=10)",
    "sound_seteffectto": "set [EFFECT=pitch] effect to (VALUE=100)",
    "sound_cleareffects": "clear sound effects",
    "sound_changevolumeby": "change volume by (VOLUME=-10)",
    "sound_setvolumeto": "set volume to (VOLUME=100) %",
    "sound_volume": "volume",
    "event_whenflagclicked": "when green flag clicked",
    "event_whenkeypressed": "when [KEY_OPTION=space] key pressed",
    "event_whenthisspriteclicked": "when this sprite clicked",
    "event_whenstageclicked": "when stage clicked",
    "event_whenbackdropswitchesto": "when backdrop switches to [BACKDROP]",
    "event_whengreaterthan": "when [WHENGREATERTHANMENU=loudness] > (VALUE=10)",
    "event_whenbroadcastreceived": "when I receive [BROADCAST_OPTION=message1]",
    "event_broadcast": "broadcast [BROADCAST_INPUT=message1]",
    "event_broadcastandwait": "broadcast [BROADCAST_INPUT=message1] and wait",
    "control_wait": "wait (DURATION=1) seconds",
    "control_repeat": "repeat (TIMES=10)",
    "control_forever": "forever",
    "control_if": "if <CONDITION> then",
    "control_if_else": "if <CONDITION> then else",
    "control_wait_until": "wait until <CONDITION>",
    "control_repeat_until": "repeat until <CONDITION>",
    "control_stop": "stop [STOP_OPTION=all]",
    "control_start_as_clone": "when I start as a clone",
    "control_create_clone_of": "create clone of [CLONE_OPTION=myself]",
    "control_delete_this_clone": "delete this clone",
    "sensing_touchingobject": "touching [TOUCHINGOBJECTMENU=mouse-pointer]?",
    "sensing_touchingcolor": "touching color (COLOR)?",
    "sensing_coloristouchingcolor": "color (COLOR) is touching (COLOR2)?",
    "sensing_distanceto": "distance to [DISTANCETOMENU=mouse-pointer]",
    "sensing_askandwait": "ask [QUESTION=What's your name?] and wait",
    "sensing_answer": "answer",
    "sensing_keypressed": "key [KEY_OPTION=space] pressed?",
    "sensing_mousedown": "mouse down?",
    "sensing_mousex": "mouse x",
    "sensing_mousey": "mouse y",
    "sensing_setdragmode": "set drag mode [DRAG_MODE=draggable]",
    "sensing_loudness": "loudness",
    "sensing_timer": "timer",
    "sensing_resettimer": "reset timer",
    "sensing_of": "[PROPERTY=backdrop #] of [OBJECT=Stage]",
    "sensing_current": "current [CURRENTMENU=year]",
    "sensing_dayssince2000": "days since 2000",
    "sensing_username": "username",
    "operator_add": "(NUM1) + (NUM2)",
    "operator_subtract": "(NUM1) - (NUM2)",
    "operator_multiply": "(NUM1) * (NUM2)",
    "operator_divide": "(NUM1) / (NUM2)",
    "operator_random": "pick random (FROM=1) to (TO=10)",
    "operator_gt": "(OPERAND1) > (OPERAND2=50)",
    "operator_lt": "(OPERAND1) < (OPERAND2=50)",
    "operator_equals": "(OPERAND1) = (OPERAND2=50)",
    "operator_and": "<OPERAND1> and <OPERAND2>",
    "operator_or": "<OPERAND1> or <OPERAND2>",
    "operator_not": "not <OPERAND>",
    "operator_join": "join [STRING1=apple] [STRING2=banana]",
    "operator_letter_of": "letter (LETTER=1) of [STRING=apple]",
    "operator_length": "length of [STRING=apple]",
    "operator_contains": "[STRING1=apple] contains [STRING2=a]?",
    "operator_mod": "(NUM1) mod (NUM2)",
    "operator_round": "round (NUM)",
    "operator_mathop": "[OPERATOR=abs] of (NUM)",
    "data_setvariableto": "set [VARIABLE] to [VALUE=0]",
    "data_changevariableby": "change [VARIABLE] by (VALUE=1)",
    "data_showvariable": "show variable [VARIABLE]",
    "data_hidevariable": "hide variable [VARIABLE]",
    "data_addtolist": "add [ITEM=thing] to [LIST]",
    "data_deleteoflist": "delete (INDEX=1) of [LIST]",
    "data_deletealloflist": "delete all of [LIST]",
    "data_insertatlist": "insert [ITEM=thing] at (INDEX=1) of [LIST]",
    "data_replaceitemoflist": "replace item (INDEX=1) of [LIST] with [ITEM=thing]",
    "data_itemoflist": "item (INDEX=1) of [LIST]",
    "data_itemnumoflist": "item # of [ITEM=thing] in [LIST]",
    "data_lengthoflist": "length of [LIST]",
    "data_listcontainsitem": "[LIST] contains [ITEM=thing]?",
    "data_showlist": "show list [LIST]",
    "data_hidelist": "hide list [LIST]",
}
"""English block texts (scratch-blocks' en messages; defaults from scratch-gui's make-toolbox-xml)."""

_SPRITE_ONLY = {
    *(op for op in _TEMPLATES if op.startswith("motion_")),
    "looks_sayforsecs", "looks_say", "looks_thinkforsecs", "looks_think", "looks_switchcostumeto",
    "looks_nextcostume", "looks_changesizeby", "looks_setsizeto", "looks_show", "looks_hide", "looks_gotofrontback",
    "looks_goforwardbackwardlayers", "looks_costumenumbername", "looks_size", "event_whenthisspriteclicked",
    "control_start_as_clone", "control_delete_this_clone", "sensing_touchingobject", "sensing_touchingcolor",
    "sensing_coloristouchingcolor", "sensing_distanceto", "sensing_setdragmode",
}  # fmt: skip
"""Blocks the Stage's palette leaves out (make-toolbox-xml's ``isStage`` branches)."""

_STAGE_ONLY = {"event_whenstageclicked", "looks_switchbackdroptoandwait"}

_BOOLEANS = {
    "operator_gt", "operator_lt", "operator_equals", "operator_and", "operator_or", "operator_not",
    "operator_contains", "sensing_touchingobject", "sensing_touchingcolor", "sensing_coloristouchingcolor",
    "sensing_keypressed", "sensing_mousedown", "data_listcontainsitem", "argument_reporter_boolean",
}  # fmt: skip

_MENU_WORDS = {
    "_random_": "random position",
    "_mouse_": "mouse-pointer",
    "_myself_": "myself",
    "_stage_": "Stage",
    "_edge_": "edge",
}
_SLOT = re.compile(r"([(\[<])([A-Z0-9_]+)(?:=([^)\]>]*))?([)\]>])")
_ORDINALS = ("first", "second", "third", "fourth", "fifth", "sixth")
_CLOSE = {"(": ")", "[": "]", "<": ">"}
_MAX_LABEL = 90
_MAX_VALUE = 24

Part = str | tuple[str, str, str]
"""Literal text, or a slot: (opening bracket, input or field name, palette default)."""


def offered_in_palette(opcode: str, is_stage: bool) -> bool:
    """Whether the palette of a sprite (or of the Stage) shows ``opcode``: a flyout task needs it there."""
    if opcode not in _TEMPLATES or opcode.startswith("data_"):
        return False  # a variable's blocks name one variable: the task would have to say which
    return opcode not in (_SPRITE_ONLY if is_stage else _STAGE_ONLY)


def palette_offers(blocks: Mapping[str, Any], block_id: str, is_stage: bool) -> bool:
    """Whether the palette has a block like this one: same opcode, nothing but shadows in its inputs."""
    block = blocks.get(block_id)
    if not isinstance(block, dict) or not offered_in_palette(str(block.get("opcode")), is_stage):
        return False
    for entry in block.get("inputs", {}).values():
        for ref in entry[1:3] if isinstance(entry, list) else [None]:
            variable = isinstance(ref, list) and ref[:1] in ([12], [13])  # compact [12, name, id]
            child = blocks.get(ref) if isinstance(ref, str) else {"shadow": not variable}
            if not isinstance(child, dict) or not child.get("shadow"):
                return False  # a block (or a compact variable) nested in it
    return True


def is_boolean(opcode: str) -> bool:
    """Whether ``opcode`` is a hexagonal (boolean) block: a slot holding it is drawn ``<...>``."""
    return opcode in _BOOLEANS


def palette_label(opcode: str) -> str:
    """The text of ``opcode`` as the palette shows it, defaults in its slots."""
    parts = template_parts(opcode)
    if parts is None:
        return _words(opcode)
    return _squash("".join(p if isinstance(p, str) else f"{p[0]}{p[2]}{_CLOSE[p[0]]}" for p in parts))


def block_label(blocks: Mapping[str, Any], block_id: str, depth: int = 0) -> str:
    """The text of a block on the workspace, reporters nested in it shown two levels deep."""
    block = blocks.get(block_id)
    if depth > 3:  # only a definition pointing at itself gets here
        return "…"
    if not isinstance(block, dict) or not isinstance(block.get("opcode"), str):
        return "?"
    opcode = block["opcode"]
    if opcode in ("data_variable", "data_listcontents") or opcode.startswith("argument_reporter"):
        value = next((v for f in ("VARIABLE", "LIST", "VALUE") if (v := _field(block, f)) is not None), "?")
        return _value(value)
    if opcode == "procedures_definition":
        held = _held(block, "custom_block")
        return _squash("define " + (block_label(blocks, held, depth + 1) if isinstance(held, str) else ""))
    parts = _parts_of(block)
    if parts is None:
        return _words(opcode)
    text = "".join(p if isinstance(p, str) else _slot_text(blocks, block, p, depth) for p in parts)
    return _squash(text)


def slot_phrase(blocks: Mapping[str, Any], block_id: str, input_name: str) -> str:
    """How an instruction names input ``input_name`` of a block: "the slot", "the second slot"."""
    block = blocks.get(block_id)
    parts = _parts_of(block) if isinstance(block, dict) else None
    fields = block.get("fields") if isinstance(block, dict) else None
    fields = fields if isinstance(fields, dict) else {}
    slots = [p[1] for p in parts or () if not isinstance(p, str) and p[1] not in fields]
    if input_name not in slots:
        return f"the {input_name.lower().replace('_', ' ')} input"
    if len(slots) == 1:
        return "the slot"
    index = slots.index(input_name)
    return f"the {_ORDINALS[index] if index < len(_ORDINALS) else f'#{index + 1}'} slot (from the left)"


def templated_opcodes() -> tuple[str, ...]:
    """The opcodes with an English text here (the Scratch 3 blocks of the standard palette)."""
    return tuple(_TEMPLATES)


def template_parts(opcode: str) -> list[Part] | None:
    """``opcode``'s English text as literal words and slots (bracket, input or field name, palette default)."""
    template = _TEMPLATES.get(opcode)
    if template is None:
        return None
    parts: list[Part] = []
    last = 0
    for match in _SLOT.finditer(template):
        parts += [template[last : match.start()], (match.group(1), match.group(2), match.group(3) or "")]
        last = match.end()
    return [*parts, template[last:]]


def _parts_of(block: Mapping[str, Any]) -> list[Part] | None:
    """Template parts; a custom block's come from its ``proccode`` ("jump %s times")."""
    opcode = block.get("opcode")
    mutation = block.get("mutation")
    if opcode not in ("procedures_call", "procedures_prototype") or not isinstance(mutation, dict):
        return template_parts(str(opcode))
    proccode = mutation.get("proccode")
    try:
        ids = json.loads(mutation.get("argumentids") or "[]")
    except (TypeError, ValueError, RecursionError):
        ids = []
    if not isinstance(proccode, str) or not isinstance(ids, list):
        return None
    parts: list[Part] = []
    pieces = re.split(r"(%[snb])", proccode)
    arguments = iter(ids)
    for piece in pieces:
        if piece in ("%s", "%n", "%b"):
            argument = next(arguments, None)
            parts.append(("<" if piece == "%b" else "(", str(argument), "") if argument is not None else "()")
        else:
            parts.append(piece)
    return parts


def _slot_text(blocks: Mapping[str, Any], block: Mapping[str, Any], slot: tuple[str, str, str], depth: int) -> str:
    bracket, name, _ = slot
    close = _CLOSE[bracket]
    field = _field(block, name)
    if field is not None:
        return f"{bracket}{_value(field)}{close}"
    held = _held(block, name)
    if isinstance(held, list) and len(held) >= 2:
        return f"({_value(held[1])})" if held[0] in (12, 13) else f"{bracket}{_value(held[1])}{close}"
    child = blocks.get(held) if isinstance(held, str) else None
    if not isinstance(child, dict):
        return f"{bracket}{close}"
    if child.get("shadow"):
        fields = child.get("fields")
        first = next(iter(fields.values()), None) if isinstance(fields, dict) and fields else None
        value = first[0] if isinstance(first, list) and first else first
        return f"{bracket}{_value(value if value is not None else '')}{close}"
    opening = "<" if is_boolean(str(child.get("opcode"))) else "("
    inner = block_label(blocks, held, depth + 1) if depth < 2 else "…"
    return f"{opening}{inner}{_CLOSE[opening]}"


def _held(block: Mapping[str, Any], name: str) -> Any:
    """What input ``name`` shows: its block, else its shadow (an id or a compact primitive)."""
    inputs = block.get("inputs")
    entry = inputs.get(name) if isinstance(inputs, dict) else None
    if not isinstance(entry, list) or len(entry) < 2:
        return None
    return entry[1] if entry[1] is not None else (entry[2] if len(entry) > 2 else None)


def _field(block: Mapping[str, Any], name: str) -> Any:
    fields = block.get("fields")
    value = fields.get(name) if isinstance(fields, dict) else None
    return value[0] if isinstance(value, list) and value else value


def _value(value: Any) -> str:
    """A slot's content, one line and short (project text is arbitrary)."""
    text = _squash(str(value))
    text = _MENU_WORDS.get(text, text)
    return text if len(text) <= _MAX_VALUE else text[: _MAX_VALUE - 1] + "…"


def _squash(text: str) -> str:
    text = " ".join("".join(c if c.isprintable() else " " for c in text).split())
    return text if len(text) <= _MAX_LABEL else text[: _MAX_LABEL - 1] + "…"


def _words(opcode: str) -> str:
    """An unknown opcode in words: ``pen_penDown`` -> "penDown (pen)"."""
    prefix, _, rest = opcode.partition("_")
    return _squash(f"{rest.replace('_', ' ')} ({prefix})" if rest else opcode)
