"""Projects of compute/power_of_number (rebuild with `python tasks/build_projects.py`)."""

from scratchworld_dist.sb3 import Project, block, circle_costume, variable


def _project() -> Project:
    project = Project()
    project.sprite("Robot", costume=circle_costume("robot", 30, "#29b6f6"))
    return project


def initial() -> Project:
    project = _project()
    project.sprites[0].script(
        block("event_whenflagclicked"),
        block("sensing_askandwait", QUESTION="Enter the base"),
    )
    return project


def golden() -> Project:
    project = _project()
    robot = project.sprites[0].variable("base").variable("exponent").variable("result")
    robot.script(
        block("event_whenflagclicked"),
        block("sensing_askandwait", QUESTION="Enter the base"),
        block("data_setvariableto", VARIABLE="base", VALUE=block("sensing_answer")),
        block("sensing_askandwait", QUESTION="Enter the exponent"),
        block("data_setvariableto", VARIABLE="exponent", VALUE=block("sensing_answer")),
        block("data_setvariableto", VARIABLE="result", VALUE=1),
        block(
            "control_repeat",
            TIMES=variable("exponent"),
            SUBSTACK=[
                block(
                    "data_setvariableto",
                    VARIABLE="result",
                    VALUE=block("operator_multiply", NUM1=variable("result"), NUM2=variable("base")),
                )
            ],
        ),
        block("looks_say", MESSAGE=variable("result")),
    )
    return project
