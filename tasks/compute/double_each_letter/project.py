"""Projects of compute/double_each_letter (rebuild with `python tasks/build_projects.py`)."""

from scratchworld_dist.sb3 import Project, block, circle_costume, variable


def _project() -> Project:
    project = Project()
    project.sprite("Parrot", costume=circle_costume("parrot", 30, "#43a047"))
    return project


def initial() -> Project:
    project = _project()
    project.sprites[0].script(
        block("event_whenflagclicked"),
        block("sensing_askandwait", QUESTION="Say a word"),
    )
    return project


def golden() -> Project:
    project = _project()
    parrot = project.sprites[0].variable("word").variable("index").variable("doubled").variable("letter")
    parrot.script(
        block("event_whenflagclicked"),
        block("sensing_askandwait", QUESTION="Say a word"),
        block("data_setvariableto", VARIABLE="word", VALUE=block("sensing_answer")),
        block("data_setvariableto", VARIABLE="doubled", VALUE=""),
        block("data_setvariableto", VARIABLE="index", VALUE=1),
        block(
            "control_repeat",
            TIMES=block("operator_length", STRING=variable("word")),
            SUBSTACK=[
                block(
                    "data_setvariableto",
                    VARIABLE="letter",
                    VALUE=block("operator_letter_of", LETTER=variable("index"), STRING=variable("word")),
                ),
                block(
                    "data_setvariableto",
                    VARIABLE="doubled",
                    VALUE=block(
                        "operator_join",
                        STRING1=variable("doubled"),
                        STRING2=block("operator_join", STRING1=variable("letter"), STRING2=variable("letter")),
                    ),
                ),
                block("data_changevariableby", VARIABLE="index", VALUE=1),
            ],
        ),
        block("looks_say", MESSAGE=variable("doubled")),
    )
    return project
