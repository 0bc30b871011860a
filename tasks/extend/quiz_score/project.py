"""Projects of extend/quiz_score (rebuild with `python tasks/build_projects.py`)."""

from scratchworld_dist.sb3 import Block, Project, block, circle_costume, variable

QUESTIONS = [("What is 7 + 5?", 12), ("What is 9 - 3?", 6)]


def _quiz(scoring: bool) -> Project:
    project = Project()
    quizzer = project.sprite("Quizzer", costume=circle_costume("quizzer", 30, "#0fbd8c"))
    blocks: list[Block] = [block("event_whenflagclicked")]
    if scoring:
        project.stage.variable("score", 0)
        blocks.append(block("data_setvariableto", VARIABLE="score", VALUE=0))
    for question, right in QUESTIONS:
        correct = [block("looks_sayforsecs", MESSAGE="Correct!", SECS=0.5)]
        if scoring:
            correct.insert(0, block("data_changevariableby", VARIABLE="score", VALUE=1))
        blocks += [
            block("sensing_askandwait", QUESTION=question),
            block(
                "control_if_else",
                CONDITION=block("operator_equals", OPERAND1=block("sensing_answer"), OPERAND2=right),
                SUBSTACK=correct,
                SUBSTACK2=[block("looks_sayforsecs", MESSAGE="Wrong!", SECS=0.5)],
            ),
        ]
    if scoring:
        blocks.append(block("looks_say", MESSAGE=block("operator_join", STRING1="Score: ", STRING2=variable("score"))))
    quizzer.script(*blocks)
    return project


def initial() -> Project:
    """The working base: two questions with feedback, no score."""
    return _quiz(scoring=False)


def golden() -> Project:
    return _quiz(scoring=True)
