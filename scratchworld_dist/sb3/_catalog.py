"""The slots of the blocks the project builder knows: which names are inputs, and of what kind.

Scratch stores literals in shadow blocks whose type depends on the slot (a number slot, a text
slot, a dropdown menu...). The builder needs that to write project.json the way the editor
does, and knowing the slots lets it reject a misspelt argument instead of writing a block the
VM silently ignores. Facts from the Scratch 3 block definitions.
"""

from __future__ import annotations

from dataclasses import dataclass

# Primitive shadow opcodes and their compact codes in project.json.
PRIMITIVE_CODES = {
    "math_number": 4,
    "math_positive_number": 5,
    "math_whole_number": 6,
    "math_integer": 7,
    "math_angle": 8,
    "colour_picker": 9,
    "text": 10,
}


@dataclass(frozen=True)
class Slot:
    """One input of a block: a primitive shadow, a menu shadow, a boolean, a stack or a broadcast."""

    kind: str  # "primitive" | "menu" | "boolean" | "stack" | "broadcast"
    shadow: str = ""  # primitive or menu shadow opcode
    menu_field: str = ""  # the field inside a menu shadow
    default: str = ""  # value of a menu shadow hidden under a reporter


NUM = Slot("primitive", "math_number")
POS = Slot("primitive", "math_positive_number")
WHOLE = Slot("primitive", "math_whole_number")
INT = Slot("primitive", "math_integer")
ANGLE = Slot("primitive", "math_angle")
COLOR = Slot("primitive", "colour_picker")
TEXT = Slot("primitive", "text")
BOOL = Slot("boolean")
STACK = Slot("stack")
BROADCAST = Slot("broadcast")


def menu(shadow: str, field: str, default: str) -> Slot:
    return Slot("menu", shadow, field, default)


@dataclass(frozen=True)
class BlockShape:
    inputs: dict[str, Slot]
    fields: frozenset[str] = frozenset()


def _shape(fields: tuple[str, ...] = (), **inputs: Slot) -> BlockShape:
    return BlockShape(inputs, frozenset(fields))


_NONE = _shape()
VARIABLE_FIELD = ("VARIABLE",)
LIST_FIELD = ("LIST",)

SHAPES: dict[str, BlockShape] = {
    # Motion
    "motion_movesteps": _shape(STEPS=NUM),
    "motion_turnright": _shape(DEGREES=NUM),
    "motion_turnleft": _shape(DEGREES=NUM),
    "motion_goto": _shape(TO=menu("motion_goto_menu", "TO", "_random_")),
    "motion_gotoxy": _shape(X=NUM, Y=NUM),
    "motion_glideto": _shape(SECS=NUM, TO=menu("motion_glideto_menu", "TO", "_random_")),
    "motion_glidesecstoxy": _shape(SECS=NUM, X=NUM, Y=NUM),
    "motion_pointindirection": _shape(DIRECTION=ANGLE),
    "motion_pointtowards": _shape(TOWARDS=menu("motion_pointtowards_menu", "TOWARDS", "_mouse_")),
    "motion_changexby": _shape(DX=NUM),
    "motion_setx": _shape(X=NUM),
    "motion_changeyby": _shape(DY=NUM),
    "motion_sety": _shape(Y=NUM),
    "motion_ifonedgebounce": _NONE,
    "motion_setrotationstyle": _shape(("STYLE",)),
    "motion_xposition": _NONE,
    "motion_yposition": _NONE,
    "motion_direction": _NONE,
    # Looks
    "looks_sayforsecs": _shape(MESSAGE=TEXT, SECS=NUM),
    "looks_say": _shape(MESSAGE=TEXT),
    "looks_thinkforsecs": _shape(MESSAGE=TEXT, SECS=NUM),
    "looks_think": _shape(MESSAGE=TEXT),
    "looks_switchcostumeto": _shape(COSTUME=menu("looks_costume", "COSTUME", "")),
    "looks_nextcostume": _NONE,
    "looks_switchbackdropto": _shape(BACKDROP=menu("looks_backdrops", "BACKDROP", "next backdrop")),
    "looks_nextbackdrop": _NONE,
    "looks_changesizeby": _shape(CHANGE=NUM),
    "looks_setsizeto": _shape(SIZE=NUM),
    "looks_changeeffectby": _shape(("EFFECT",), CHANGE=NUM),
    "looks_seteffectto": _shape(("EFFECT",), VALUE=NUM),
    "looks_cleargraphiceffects": _NONE,
    "looks_show": _NONE,
    "looks_hide": _NONE,
    "looks_gotofrontback": _shape(("FRONT_BACK",)),
    "looks_goforwardbackwardlayers": _shape(("FORWARD_BACKWARD",), NUM=INT),
    "looks_costumenumbername": _shape(("NUMBER_NAME",)),
    "looks_backdropnumbername": _shape(("NUMBER_NAME",)),
    "looks_size": _NONE,
    # Sound
    "sound_play": _shape(SOUND_MENU=menu("sound_sounds_menu", "SOUND_MENU", "")),
    "sound_playuntildone": _shape(SOUND_MENU=menu("sound_sounds_menu", "SOUND_MENU", "")),
    "sound_stopallsounds": _NONE,
    "sound_setvolumeto": _shape(VOLUME=NUM),
    "sound_changevolumeby": _shape(VOLUME=NUM),
    "sound_volume": _NONE,
    # Events
    "event_whenflagclicked": _NONE,
    "event_whenkeypressed": _shape(("KEY_OPTION",)),
    "event_whenthisspriteclicked": _NONE,
    "event_whenstageclicked": _NONE,
    "event_whenbackdropswitchesto": _shape(("BACKDROP",)),
    "event_whenbroadcastreceived": _shape(("BROADCAST_OPTION",)),
    "event_broadcast": _shape(BROADCAST_INPUT=BROADCAST),
    "event_broadcastandwait": _shape(BROADCAST_INPUT=BROADCAST),
    # Control
    "control_wait": _shape(DURATION=POS),
    "control_repeat": _shape(TIMES=WHOLE, SUBSTACK=STACK),
    "control_forever": _shape(SUBSTACK=STACK),
    "control_if": _shape(CONDITION=BOOL, SUBSTACK=STACK),
    "control_if_else": _shape(CONDITION=BOOL, SUBSTACK=STACK, SUBSTACK2=STACK),
    "control_wait_until": _shape(CONDITION=BOOL),
    "control_repeat_until": _shape(CONDITION=BOOL, SUBSTACK=STACK),
    "control_stop": _shape(("STOP_OPTION",)),
    "control_start_as_clone": _NONE,
    "control_create_clone_of": _shape(CLONE_OPTION=menu("control_create_clone_of_menu", "CLONE_OPTION", "_myself_")),
    "control_delete_this_clone": _NONE,
    # Sensing
    "sensing_touchingobject": _shape(
        TOUCHINGOBJECTMENU=menu("sensing_touchingobjectmenu", "TOUCHINGOBJECTMENU", "_mouse_")
    ),
    "sensing_touchingcolor": _shape(COLOR=COLOR),
    "sensing_distanceto": _shape(DISTANCETOMENU=menu("sensing_distancetomenu", "DISTANCETOMENU", "_mouse_")),
    "sensing_askandwait": _shape(QUESTION=TEXT),
    "sensing_answer": _NONE,
    "sensing_keypressed": _shape(KEY_OPTION=menu("sensing_keyoptions", "KEY_OPTION", "space")),
    "sensing_mousedown": _NONE,
    "sensing_mousex": _NONE,
    "sensing_mousey": _NONE,
    "sensing_timer": _NONE,
    "sensing_resettimer": _NONE,
    "sensing_of": _shape(("PROPERTY",), OBJECT=menu("sensing_of_object_menu", "OBJECT", "_stage_")),
    "sensing_current": _shape(("CURRENTMENU",)),
    # Operators
    "operator_add": _shape(NUM1=NUM, NUM2=NUM),
    "operator_subtract": _shape(NUM1=NUM, NUM2=NUM),
    "operator_multiply": _shape(NUM1=NUM, NUM2=NUM),
    "operator_divide": _shape(NUM1=NUM, NUM2=NUM),
    "operator_random": _shape(FROM=NUM, TO=NUM),
    "operator_gt": _shape(OPERAND1=TEXT, OPERAND2=TEXT),
    "operator_lt": _shape(OPERAND1=TEXT, OPERAND2=TEXT),
    "operator_equals": _shape(OPERAND1=TEXT, OPERAND2=TEXT),
    "operator_and": _shape(OPERAND1=BOOL, OPERAND2=BOOL),
    "operator_or": _shape(OPERAND1=BOOL, OPERAND2=BOOL),
    "operator_not": _shape(OPERAND=BOOL),
    "operator_join": _shape(STRING1=TEXT, STRING2=TEXT),
    "operator_letter_of": _shape(LETTER=WHOLE, STRING=TEXT),
    "operator_length": _shape(STRING=TEXT),
    "operator_contains": _shape(STRING1=TEXT, STRING2=TEXT),
    "operator_mod": _shape(NUM1=NUM, NUM2=NUM),
    "operator_round": _shape(NUM=NUM),
    "operator_mathop": _shape(("OPERATOR",), NUM=NUM),
    # Variables and lists
    "data_variable": _shape(VARIABLE_FIELD),
    "data_setvariableto": _shape(VARIABLE_FIELD, VALUE=TEXT),
    "data_changevariableby": _shape(VARIABLE_FIELD, VALUE=NUM),
    "data_showvariable": _shape(VARIABLE_FIELD),
    "data_hidevariable": _shape(VARIABLE_FIELD),
    "data_listcontents": _shape(LIST_FIELD),
    "data_addtolist": _shape(LIST_FIELD, ITEM=TEXT),
    "data_deleteoflist": _shape(LIST_FIELD, INDEX=INT),
    "data_deletealloflist": _shape(LIST_FIELD),
    "data_insertatlist": _shape(LIST_FIELD, ITEM=TEXT, INDEX=INT),
    "data_replaceitemoflist": _shape(LIST_FIELD, INDEX=INT, ITEM=TEXT),
    "data_itemoflist": _shape(LIST_FIELD, INDEX=INT),
    "data_itemnumoflist": _shape(LIST_FIELD, ITEM=TEXT),
    "data_lengthoflist": _shape(LIST_FIELD),
    "data_listcontainsitem": _shape(LIST_FIELD, ITEM=TEXT),
    # Pen (an extension: a project using it lists "pen" in its extensions)
    "pen_clear": _NONE,
    "pen_stamp": _NONE,
    "pen_penDown": _NONE,
    "pen_penUp": _NONE,
    "pen_setPenColorToColor": _shape(COLOR=COLOR),
    "pen_changePenSizeBy": _shape(SIZE=NUM),
    "pen_setPenSizeTo": _shape(SIZE=NUM),
}

EXTENSIONS = ("pen",)
"""Extensions whose blocks the catalog knows: an opcode ``<extension>_...`` needs it loaded."""
