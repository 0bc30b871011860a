"""Hand-made projects for the grader audit: every mutation operator and every refactoring has a place in them."""

from __future__ import annotations

from typing import Any

from scratchworld_dist.sb3 import Project, block, circle_costume, list_contents, variable


def mutation_project() -> Project:
    """One place at least for each mutation operator, plus a loose block (no hat: it never runs)."""
    project = Project()
    project.stage.variable("score", 0).variable("lives", 3)
    project.stage.list("items", ["a"]).list("names", ["b"])
    cat = project.sprite("Cat", costume=circle_costume("cat", 12, "#f80")).variable("speed", 1)
    cat.script(
        block("event_whenflagclicked"),
        block("data_setvariableto", VARIABLE="score", VALUE=0),
        block("data_setvariableto", VARIABLE="speed", VALUE=5),
        block(
            "control_repeat",
            TIMES=3,
            SUBSTACK=[
                block(
                    "data_changevariableby",
                    VARIABLE="score",
                    VALUE=block("operator_add", NUM1=variable("speed"), NUM2=1),
                ),
                block("control_wait", DURATION=0.5),
            ],
        ),
        block(
            "control_if_else",
            CONDITION=block(
                "operator_and",
                OPERAND1=block("operator_gt", OPERAND1=variable("score"), OPERAND2=10),
                OPERAND2=block("operator_not", OPERAND=block("operator_lt", OPERAND1=variable("lives"), OPERAND2=1)),
            ),
            SUBSTACK=[block("looks_say", MESSAGE="Big")],
            SUBSTACK2=[block("looks_say", MESSAGE="small")],
        ),
        block("data_addtolist", LIST="items", ITEM=block("operator_multiply", NUM1=variable("score"), NUM2=2)),
        block("event_broadcast", BROADCAST_INPUT="go"),
        block(
            "control_forever",
            SUBSTACK=[
                block("motion_movesteps", STEPS=block("operator_subtract", NUM1=10, NUM2=variable("speed"))),
                block("motion_turnright", DEGREES=block("operator_divide", NUM1=variable("score"), NUM2=2)),
            ],
        ),
    )
    cat.script(
        block("event_whenbroadcastreceived", BROADCAST_OPTION="go"),
        block("looks_say", MESSAGE=block("operator_join", STRING1="hello", STRING2=list_contents("items"))),
        block("data_changevariableby", VARIABLE="lives", VALUE=block("operator_mod", NUM1=variable("score"), NUM2=3)),
    )
    cat.script(block("event_whenkeypressed", KEY_OPTION="space"), block("event_broadcast", BROADCAST_INPUT="stop"))
    cat.script(block("event_whenbroadcastreceived", BROADCAST_OPTION="stop"), block("looks_hide"))
    cat.script(block("looks_show"), block("motion_movesteps", STEPS=99), x=600, y=40)  # loose: no hat
    return project


def refactoring_project() -> Project:
    """A place for each refactoring, and places where one must not be made (an effect in an operand, two
    scripts started by one event, a sprite that clones itself)."""
    project = Project()
    project.stage.variable("points", 0)
    project.stage.list("log", [])
    dog = project.sprite("Dog", costume=circle_costume("dog", 12, "#08f")).variable("steps", 0)
    dog.script(
        block("event_whenflagclicked"),
        block("data_setvariableto", VARIABLE="points", VALUE=0),
        block(
            "control_repeat",
            TIMES=4,
            SUBSTACK=[
                block(
                    "data_changevariableby",
                    VARIABLE="points",
                    VALUE=block("operator_add", NUM1=variable("steps"), NUM2=1),
                ),
                block("motion_movesteps", STEPS=10),
            ],
        ),
        block("event_broadcastandwait", BROADCAST_INPUT="half"),
        block(
            "looks_say",
            MESSAGE=block("operator_multiply", NUM1=variable("points"), NUM2=block("operator_random", FROM=1, TO=2)),
        ),
        block("data_addtolist", LIST="log", ITEM=variable("points")),
    )
    dog.script(
        block("event_whenbroadcastreceived", BROADCAST_OPTION="half"),
        block(
            "control_if",
            CONDITION=block(
                "operator_and",
                OPERAND1=block("sensing_keypressed", KEY_OPTION="space"),
                OPERAND2=block("operator_gt", OPERAND1=variable("points"), OPERAND2=3),
            ),
            SUBSTACK=[block("data_changevariableby", VARIABLE="steps", VALUE=1)],
        ),
        block(
            "control_if",
            CONDITION=block(
                "operator_or",
                OPERAND1=block("operator_equals", OPERAND1=block("operator_random", FROM=1, TO=6), OPERAND2=6),
                OPERAND2=block("sensing_mousedown"),
            ),
            SUBSTACK=[block("looks_say", MESSAGE="six")],
        ),
    )
    dog.script(block("event_whenflagclicked"), block("looks_show"))  # shares the flag with the first script
    dog.script(block("event_whenthisspriteclicked"), block("motion_turnright", DEGREES=15))
    owl = project.sprite("Owl", costume=circle_costume("owl", 10, "#666"), x=100)
    owl.script(
        block("event_whenflagclicked"),
        block("control_repeat", TIMES=block("operator_add", NUM1=1, NUM2=1), SUBSTACK=[block("looks_nextcostume")]),
        block("looks_say", MESSAGE=block("sensing_of", PROPERTY="steps", OBJECT="Dog")),
        block("event_broadcastandwait", BROADCAST_INPUT="half"),
        block("control_create_clone_of", CLONE_OPTION="_myself_"),
    )
    return project


def with_monitor(project: dict[str, Any], name: str) -> dict[str, Any]:
    """The project with a stage monitor showing the global variable ``name`` (the builder writes none)."""
    stage = project["targets"][0]
    var_id = next(i for i, entry in stage["variables"].items() if entry[0] == name)
    monitor = {
        "id": var_id,
        "mode": "default",
        "opcode": "data_variable",
        "params": {"VARIABLE": name},
        "spriteName": None,
        "value": 0,
        "width": 0,
        "height": 0,
        "x": 5,
        "y": 5,
        "visible": True,
        "sliderMin": 0,
        "sliderMax": 100,
        "isDiscrete": True,
    }
    return {**project, "monitors": [monitor]}
