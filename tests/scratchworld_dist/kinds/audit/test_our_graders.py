"""Our suite's graders fail mutants that used to pass them: one former grader hole per kind of weakness the
audit found (timing, both ends of a random range, a start position, the order of a say and a wait, a question
asked with no text). The whole measurement is ``scratchworld audit tasks``; this keeps each fix from being
undone unnoticed."""

from __future__ import annotations

import io
import json
import zipfile

import pytest

from scratchworld_dist.kinds.audit.variants import enumerate_mutants
from scratchworld_dist.kinds.tasks import read_task
from scratchworld_dist.sb3 import Sb3Archive
from scratchworld_dist.suites import load_suite
from tests.conftest import SUITE_DIR
from workers.evaluation import Evaluator

pytestmark = [pytest.mark.browser, pytest.mark.slow]

FORMER_HOLES = [
    ("quiz_score", "Quizzer: number '0.5' -> '1' in looks_sayforsecs"),  # feedback shown twice as long
    ("star_shower", "Star: number '200' -> '199' in operator_random"),  # the right end never reached
    ("guess_hints_backwards", "Owl: number '100' -> '99' in operator_random"),
    ("traffic_light_skips_yellow", "Stage: wait '0.3' -> '0' in control_wait"),  # yellow never shows
    ("countdown_launch", "Commander: swap looks_say and control_wait"),  # each number said 0.3 s late
    ("bouncing_ball_stuck", "Ball: number '0' -> '1' in motion_gotoxy"),  # starts off the centre
    ("sum_two_numbers", "Calculator: text 'Enter the first number' -> ''"),  # asks with no question
]


@pytest.mark.parametrize(("task_id", "change"), FORMER_HOLES, ids=[task for task, _ in FORMER_HOLES])
async def test_a_former_grader_hole_is_killed(task_id: str, change: str, evaluator: Evaluator) -> None:
    task = read_task(load_suite(SUITE_DIR).task(task_id))
    golden = task.payload.golden_project
    assert golden is not None
    with zipfile.ZipFile(io.BytesIO(golden)) as archive:
        project = json.loads(archive.read("project.json"))
    mutant = next(m for m in enumerate_mutants(project) if m.description.startswith(change))
    result = await evaluator.evaluate(Sb3Archive(golden).with_project(mutant.project), task.payload.evaluation)
    assert result.error is None and not result.success, (mutant.description, result.tests)
