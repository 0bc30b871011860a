"""A misjudged variant compared with its golden in a real page, by behaviour: the tests' own run, then the task's
exploration. A doubler that treats the empty answer otherwise passes a test that answers 3, and differs only when
the exploration answers nothing: a hole for a task that allows any answer, outside the task for one that asks for
numbers; a variant written otherwise is equivalent in every run; a grader that never starts the program, or reads
nothing it does, is named vacuous."""

from __future__ import annotations

import pytest

from scratchworld_dist.sb3 import Project, block, circle_costume
from workers.contract import EvaluationSpec, ProjectLimits
from workers.evaluation import Evaluator
from workers.kinds.audit import ExplorationEpisode, ExplorationPlan, Stimulus
from workers.kinds.audit._judge import judged_by_behaviour
from workers.kinds.audit._vacuity import grader_check

pytestmark = pytest.mark.browser

ANSWERS_THREE = """
module.exports = async (vm) => {
  const said = [];
  vm.runtime.on('SAY', (target, type, text) => said.push(String(text)));
  vm.runtime.on('QUESTION', (q) => { if (q !== null) setTimeout(() => vm.runtime.emit('ANSWER', '3'), 50); });
  vm.greenFlag();
  await new Promise((resolve) => setTimeout(resolve, 1000));
  vm.runtime.stopAll();
  return {details: [{name: 'doubles 3', passed: said.includes('6')}]};
};
"""

NEVER_STARTS = "module.exports = async () => ({details: [{name: 'fine', passed: true}]});"

READS_NOTHING_IT_DOES = """
module.exports = async (vm) => {
  vm.greenFlag();
  await new Promise((resolve) => setTimeout(resolve, 300));
  const cat = vm.runtime.targets.find((t) => t.isOriginal && !t.isStage);
  return {details: [{name: 'the cat is big enough', passed: cat.size >= 0}]};
};
"""

SPEC = EvaluationSpec(script_name="doubles.js", script_source=ANSWERS_THREE, timeout_s=20, clock="virtual")
LIMITS = ProjectLimits()


def doubler(empty_says: str = "nothing", commuted: bool = False) -> bytes:
    """Cat asks, then says twice the answer, or ``empty_says`` when the answer is empty."""
    project = Project()
    cat = project.sprite("Cat", costume=circle_costume("a", 10, "#36c"))
    twice = (
        block("operator_multiply", NUM1=2, NUM2=block("sensing_answer"))
        if commuted
        else block("operator_multiply", NUM1=block("sensing_answer"), NUM2=2)
    )
    cat.script(
        block("event_whenflagclicked"),
        block("sensing_askandwait", QUESTION="n?"),
        block(
            "control_if_else",
            CONDITION=block("operator_equals", OPERAND1=block("sensing_answer"), OPERAND2=""),
            SUBSTACK=[block("looks_say", MESSAGE=empty_says)],
            SUBSTACK2=[block("looks_say", MESSAGE=twice)],
        ),
    )
    return project.to_sb3()


def plan(domain: str) -> ExplorationPlan:
    flag = [Stimulus(at_ms=0, kind="green_flag")]
    return ExplorationPlan(
        episodes=[
            ExplorationEpisode(name="seed 1, answers: numbers", seed=1, stimuli=flag, answers=["4"], span_ms=2000),
            ExplorationEpisode(name="seed 2, answers: empty", seed=2, stimuli=flag, answers=[""], span_ms=2000),
        ],
        answer_domain=domain,  # type: ignore[arg-type]
    )


async def test_a_difference_only_an_answer_the_task_rules_out_shows_is_outside_the_task(evaluator: Evaluator) -> None:
    golden, shouting = doubler(), doubler("NOTHING")
    assert (await evaluator.evaluate(shouting, SPEC)).success  # the tests pass it: misjudged, if it differs
    anything = await judged_by_behaviour(evaluator, golden, shouting, SPEC, LIMITS, plan("any"))
    numbers = await judged_by_behaviour(evaluator, golden, shouting, SPEC, LIMITS, plan("numbers"))
    assert anything is not None and numbers is not None
    assert anything.observed == "differs" and numbers.observed == "outside_task"
    for found in (anything, numbers):
        assert found.shown_by is not None and found.shown_by.run == "seed 2, answers: empty"
        assert found.shown_by.answers == [""] and found.shown_by.stimulus == "green flag at 0.0 s"
        assert found.first is not None and (found.first["target"], found.first["field"]) == ("Cat", "bubble")
        assert found.difference is not None and "'NOTHING'" in found.difference
    assert numbers.runs == 3  # the tests' run and both episodes: every run was looked at before "outside"
    # Without an exploration the tests' run alone decides, as before: the blind spot.
    blind = await judged_by_behaviour(evaluator, golden, shouting, SPEC, LIMITS, None)
    assert blind is not None and blind.observed == "equivalent" and blind.runs == 1


async def test_a_variant_written_otherwise_is_equivalent_in_every_run(evaluator: Evaluator) -> None:
    found = await judged_by_behaviour(evaluator, doubler(), doubler(commuted=True), SPEC, LIMITS, plan("any"))
    assert found is not None and found.observed == "equivalent" and found.runs == 3 and found.difference is None


@pytest.mark.parametrize(
    ("script", "vacuous"),
    [(NEVER_STARTS, "never_starts"), (READS_NOTHING_IT_DOES, "observes_nothing"), (ANSWERS_THREE, None)],
    ids=["never-starts", "observes-nothing", "sound"],
)
async def test_a_grader_that_judges_nothing_is_named(script: str, vacuous: str | None, evaluator: Evaluator) -> None:
    spec = SPEC.model_copy(update={"script_source": script})
    check = await grader_check(evaluator, doubler(), spec, LIMITS, plan("any"))
    assert check is not None and check.vacuous == vacuous, check
    assert ("Cat", "bubble") in check.changes  # what the golden does: it says things
    if vacuous == "observes_nothing":
        assert check.started and ("Cat", "size") in check.reads
