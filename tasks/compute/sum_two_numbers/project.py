"""Projects of compute/sum_two_numbers (rebuild with `python tasks/build_projects.py`)."""

from scratchworld_dist.sb3 import Project, block, circle_costume, variable


def _project() -> Project:
    project = Project()
    project.sprite("Calculator", costume=circle_costume("calculator", 30, "#4c97ff"))
    return project


def initial() -> Project:
    project = _project()
    project.sprites[0].script(
        block("event_whenflagclicked"),
        block("sensing_askandwait", QUESTION="Enter the first number"),
    )
    return project


def golden() -> Project:
    project = _project()
    calculator = project.sprites[0].variable("first").variable("second")
    calculator.script(
        block("event_whenflagclicked"),
        block("sensing_askandwait", QUESTION="Enter the first number"),
        block("data_setvariableto", VARIABLE="first", VALUE=block("sensing_answer")),
        block("sensing_askandwait", QUESTION="Enter the second number"),
        block("data_setvariableto", VARIABLE="second", VALUE=block("sensing_answer")),
        block("looks_say", MESSAGE=block("operator_add", NUM1=variable("first"), NUM2=variable("second"))),
    )
    return project
