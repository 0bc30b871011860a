"""Projects of create/countdown_launch (rebuild with `python tasks/build_projects.py`)."""

from scratchworld_dist.sb3 import Project, block, circle_costume, rect_costume, variable


def _project() -> Project:
    project = Project()
    project.sprite("Commander", costume=circle_costume("commander", 25, "#ffab19"), x=-150, y=-100)
    project.sprite("Rocket", costume=rect_costume("rocket", 24, 60, "#9966ff"), x=0, y=-120)
    return project


def initial() -> Project:
    return _project()


def golden() -> Project:
    project = _project()
    project.stage.variable("count", 0)
    commander, rocket = project.sprites
    commander.script(
        block("event_whenflagclicked"),
        block("data_setvariableto", VARIABLE="count", VALUE=5),
        block(
            "control_repeat",
            TIMES=5,
            SUBSTACK=[
                block("looks_say", MESSAGE=variable("count")),
                block("control_wait", DURATION=0.3),
                block("data_changevariableby", VARIABLE="count", VALUE=-1),
            ],
        ),
        block("looks_say", MESSAGE="Liftoff!"),
        block("event_broadcast", BROADCAST_INPUT="launch"),
    )
    rocket.script(
        block("event_whenflagclicked"),
        block("motion_gotoxy", X=0, Y=-120),
    )
    rocket.script(
        block("event_whenbroadcastreceived", BROADCAST_OPTION="launch"),
        block("motion_glidesecstoxy", SECS=1, X=0, Y=150),
    )
    return project
