"""Projects of debug/guess_hints_backwards (rebuild with `python tasks/build_projects.py`).

A number-guessing game. In the initial project the "too high" test compares the wrong way
round (secret > answer instead of answer > secret), so every hint points the wrong way.
"""

from scratchworld_dist.sb3 import Project, block, circle_costume, variable

QUESTION = "Guess my number between 1 and 100!"


def _project() -> Project:
    project = Project()
    project.stage.variable("secret", 0)
    project.sprite("Owl", costume=circle_costume("owl", 35, "#8e6bbf"), x=-120, y=-40)
    return project


def _game(too_high: object) -> list:
    return [
        block("event_whenflagclicked"),
        block("data_setvariableto", VARIABLE="secret", VALUE=block("operator_random", FROM=1, TO=100)),
        block("looks_sayforsecs", MESSAGE="I'm thinking of a number...", SECS=0.5),
        block(
            "control_forever",
            SUBSTACK=[
                block("sensing_askandwait", QUESTION=QUESTION),
                block(
                    "control_if_else",
                    CONDITION=block("operator_equals", OPERAND1=block("sensing_answer"), OPERAND2=variable("secret")),
                    SUBSTACK=[
                        block("looks_say", MESSAGE="You got it!"),
                        block("control_stop", STOP_OPTION="this script"),
                    ],
                    SUBSTACK2=[
                        block(
                            "control_if_else",
                            CONDITION=too_high,
                            SUBSTACK=[block("looks_sayforsecs", MESSAGE="Too high!", SECS=0.5)],
                            SUBSTACK2=[block("looks_sayforsecs", MESSAGE="Too low!", SECS=0.5)],
                        )
                    ],
                ),
            ],
        ),
    ]


def initial() -> Project:
    project = _project()
    project.sprites[0].script(
        *_game(block("operator_gt", OPERAND1=variable("secret"), OPERAND2=block("sensing_answer")))
    )
    return project


def golden() -> Project:
    project = _project()
    project.sprites[0].script(
        *_game(block("operator_gt", OPERAND1=block("sensing_answer"), OPERAND2=variable("secret")))
    )
    return project
