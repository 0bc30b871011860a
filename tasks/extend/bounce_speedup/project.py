"""Projects of extend/bounce_speedup (rebuild with `python tasks/build_projects.py`)."""

from scratchworld_dist.sb3 import Block, Project, block, circle_costume, variable


def _ball(loop: list[Block]) -> Project:
    project = Project()
    ball = project.sprite("Ball", costume=circle_costume("ball", 15, "#ff4d4d"))
    ball.variable("speed", 15)
    ball.script(
        block("event_whenflagclicked"),
        block("motion_gotoxy", X=0, Y=0),
        block("motion_pointindirection", DIRECTION=90),
        block("data_setvariableto", VARIABLE="speed", VALUE=15),
        block("control_forever", SUBSTACK=loop),
    )
    return project


def initial() -> Project:
    """The working base: a ball bouncing left and right at a constant speed."""
    return _ball([block("motion_movesteps", STEPS=variable("speed")), block("motion_ifonedgebounce")])


def golden() -> Project:
    project = _ball(
        [
            block("motion_movesteps", STEPS=variable("speed")),
            block("data_setvariableto", VARIABLE="heading", VALUE=block("motion_direction")),
            block("motion_ifonedgebounce"),
            block(
                "control_if",
                CONDITION=block(
                    "operator_not",
                    OPERAND=block("operator_equals", OPERAND1=block("motion_direction"), OPERAND2=variable("heading")),
                ),
                SUBSTACK=[block("data_changevariableby", VARIABLE="speed", VALUE=1)],
            ),
        ]
    )
    project.sprites[0].variable("heading", 90)
    return project
