"""Projects of debug/traffic_light_skips_yellow (rebuild with `python tasks/build_projects.py`).

The stage runs the light's timing and broadcasts "go", "slow" and "stop"; the Light switches
costume when it receives each message. In the initial project the stage's second broadcast
sends "stop" instead of "slow", so the light jumps from green straight to red.
"""

from scratchworld_dist.sb3 import Project, backdrop_costume, block, circle_costume, rect_costume

COLOURS = {"green": "#2ecc40", "yellow": "#ffdc00", "red": "#ff4136"}


def _project(second_message: str) -> Project:
    project = Project(backdrop=backdrop_costume("street", "#cfd8dc"))
    project.sprite("Pole", costume=rect_costume("pole", 16, 140, "#37474f"), x=0, y=-90)
    light = project.sprite(
        "Light", costume=[circle_costume(name, 30, fill) for name, fill in COLOURS.items()], x=0, y=40
    )
    for message, costume in (("go", "green"), ("slow", "yellow"), ("stop", "red")):
        light.script(
            block("event_whenbroadcastreceived", BROADCAST_OPTION=message),
            block("looks_switchcostumeto", COSTUME=costume),
        )
    project.stage.script(
        block("event_whenflagclicked"),
        block(
            "control_forever",
            SUBSTACK=[
                block("event_broadcast", BROADCAST_INPUT="go"),
                block("control_wait", DURATION=0.6),
                block("event_broadcast", BROADCAST_INPUT=second_message),
                block("control_wait", DURATION=0.3),
                block("event_broadcast", BROADCAST_INPUT="stop"),
                block("control_wait", DURATION=0.6),
            ],
        ),
    )
    return project


def initial() -> Project:
    return _project("stop")


def golden() -> Project:
    return _project("slow")
