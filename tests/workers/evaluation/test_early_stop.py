"""Stopping at the first failing test (``EvaluationSpec.stop_at_first_failure``, the grader audit's mutants): the
tests after the first that fails do not run, the verdict is the one every test gives, a project that passes runs
every test, and without the option nothing changes. Through both suites' helpers, unchanged: our ``Harness.runTests``
and upstream's ``EvaluationUtils.runCaseWithTimeout`` (question-and-answer cases included)."""

from __future__ import annotations

import pytest

from scratchworld_dist.sb3 import Project, block, circle_costume
from tests.conftest import SUITE_DIR, UPSTREAM_DIR
from tests.support.evaluations import spec
from tests.support.projects import counter_project
from workers.contract import EarlyStop, EvalResult
from workers.evaluation import Evaluator

pytestmark = pytest.mark.browser

HARNESS = (SUITE_DIR / "harness.js").read_text()

# Three tests of the counter (counts to `target`, then says "done"); each logs that it ran. The second waits
# 20 s of virtual time: a stop after the first spares it.
OURS = """
const count = (vm) => vm.runtime.getTargetForStage().lookupVariableByNameAndType('count', '').value;
module.exports = async (vm) => Harness.runTests(vm, [
  {name: 'count reaches 10', timeoutMs: 5000, run: async () => {
    console.log('ran: count reaches 10');
    await Harness.start(vm);
    await Harness.waitUntil(() => count(vm) >= 10, {timeoutMs: 2000});
    return {passed: count(vm) === 10};
  }},
  {name: 'still 10 after a while', timeoutMs: 30000, run: async () => {
    console.log('ran: still 10 after a while');
    await Harness.start(vm);
    await Harness.wait(20000);
    return {passed: count(vm) === 10};
  }},
  {name: 'says done', timeoutMs: 5000, run: async () => {
    console.log('ran: says done');
    const speech = Harness.recordSpeech(vm);
    await Harness.start(vm);
    await Harness.wait(500);
    speech.stop();
    return {passed: speech.texts('Counter').includes('done')};
  }},
]);
"""


def ours(stop: bool) -> object:
    return spec(OURS, 60, helper_source=HARNESS, helper_global="Harness", clock="virtual", stop_at_first_failure=stop)


def ran(result: EvalResult) -> list[str]:
    return [line.removeprefix("log: ran: ") for line in result.console if line.startswith("log: ran: ")]


async def test_a_project_failing_its_first_test_stops_there(evaluator: Evaluator) -> None:
    project = counter_project(target=7).to_sb3()
    stopped = await evaluator.evaluate(project, ours(True))
    full = await evaluator.evaluate(project, ours(False))
    assert (stopped.success, full.success) == (False, False) and stopped.error is None
    assert ran(stopped) == ["count reaches 10"]
    assert ran(full) == ["count reaches 10", "still 10 after a while", "says done"]
    assert stopped.stopped_early == EarlyStop(test="count reaches 10", not_run=2) and full.stopped_early is None
    # The tests not run are counted, not passed, and not listed; the one that ran is as in the full run.
    assert (stopped.passed, stopped.total, [t.name for t in stopped.tests]) == (0, 3, ["count reaches 10"])
    assert stopped.tests[0] == full.tests[0] and stopped.warnings == []
    assert stopped.timings.script_clock_s is not None and stopped.timings.script_clock_s < 20  # the wait never ran


async def test_a_passing_project_runs_every_test(evaluator: Evaluator) -> None:
    result = await evaluator.evaluate(counter_project(target=10).to_sb3(), ours(True))
    assert (result.success, result.passed, result.total, result.stopped_early) == (True, 3, 3, None)
    assert ran(result) == ["count reaches 10", "still 10 after a while", "says done"]


async def test_a_project_failing_only_its_last_test_runs_every_test(evaluator: Evaluator) -> None:
    """Nothing is left to skip: the run is an ordinary one (no early stop recorded)."""
    project = Project()  # the counter, silent
    project.stage.variable("count", 0)
    project.sprite("Counter", costume=circle_costume("dot", 10, "#36c")).script(
        block("event_whenflagclicked"),
        block("data_setvariableto", VARIABLE="count", VALUE=0),
        block("control_repeat", TIMES=10, SUBSTACK=[block("data_changevariableby", VARIABLE="count", VALUE=1)]),
    )
    result = await evaluator.evaluate(project.to_sb3(), ours(True))
    assert (result.success, result.passed, result.total, result.stopped_early) == (False, 2, 3, None)
    assert ran(result) == ["count reaches 10", "still 10 after a while", "says done"]


# Upstream's shape: a case runner over EU.runCaseWithTimeout, details pushed and counted by the script, then
# question-and-answer cases through EU.runQuestionAnswerTestsDetailed (one runCaseWithTimeout call each).
UPSTREAM_STYLE = """
module.exports = async (vm, config, cleanup) => {
  const EU = window.EvaluationUtils;
  const runCase = async (caseName, runner) => EU.runCaseWithTimeout({
    caseName, timeoutMs: 5000,
    beforeCase: async () => { console.log('ran: ' + caseName); EU.startVM(vm); await EU.wait(300); },
    run: async () => runner(),
    afterCase: async () => { vm.runtime.stopAll(); },
  });
  const sprite = () => EU.findSprite(vm, 'Echo');
  const details = [];
  details.push(await runCase('echo exists', async () => ({passed: !!sprite()})));
  details.push(await runCase('echo is at the left', async () => ({passed: sprite().x < 0, meta: {x: sprite().x}})));
  const qa = await EU.runQuestionAnswerTestsDetailed(vm, [
    {name: 'echoes 3', input: '3', expected: 3}, {name: 'echoes 5', input: '5', expected: 5},
  ], ['number'], {timeout: 5, spriteName: 'Echo'});
  details.push(...qa.details);
  const passed = details.filter(d => d.passed).length;
  cleanup();
  return {success: passed === details.length, passed_tests: passed, total_tests: details.length, details};
};
"""


def echo_project(x: int) -> bytes:
    """Echo, at ``x``, asks for a number and says the answer."""
    project = Project()
    project.sprite("Echo", costume=circle_costume("dot", 10, "#3a6"), x=x).script(
        block("event_whenflagclicked"),
        block("sensing_askandwait", QUESTION="a number?"),
        block("looks_say", MESSAGE=block("sensing_answer")),
    )
    return project.to_sb3()


@pytest.fixture
def upstream_helper() -> str:
    """Upstream's own EvaluationUtils; skip when absent."""
    helper = UPSTREAM_DIR / "scratch-bench-api" / "api" / "evaluation_scripts" / "evaluation_utils.js"
    if not helper.is_file():
        pytest.skip(f"upstream's helper not found at {helper}")
    return helper.read_text()


@pytest.mark.upstream
@pytest.mark.parametrize(("x", "expected"), [(-100, None), (100, EarlyStop(test="echo is at the left", not_run=2))])
async def test_upstream_helpers_stop_at_the_first_failing_case(
    evaluator: Evaluator, upstream_helper: str, x: int, expected: EarlyStop | None
) -> None:
    results = [
        await evaluator.evaluate(
            echo_project(x),
            spec(UPSTREAM_STYLE, 60, helper_source=upstream_helper, clock="virtual", stop_at_first_failure=stop),
        )
        for stop in (True, False)
    ]
    stopped, full = results
    assert stopped.stopped_early == expected and full.stopped_early is None
    assert stopped.success == full.success == (expected is None)
    assert [t.name for t in full.tests] == ["echo exists", "echo is at the left", "echoes 3", "echoes 5"]
    assert [t.passed for t in full.tests] == [True, x < 0, True, True]
    if expected is None:
        assert [(t.name, t.passed) for t in stopped.tests] == [(t.name, t.passed) for t in full.tests]
        assert ran(stopped) == ["echo exists", "echo is at the left"]
    else:  # the question-and-answer cases never started the project: nobody asked, nobody answered
        assert [t.name for t in stopped.tests] == ["echo exists", "echo is at the left"]
        assert (stopped.passed, stopped.total) == (1, 4)
        assert stopped.timings.script_clock_s < full.timings.script_clock_s
