"""Evaluation: verdicts, every failure class, hard timeouts, and isolation between projects."""

from __future__ import annotations

import json

import pytest

from tests.support.evaluations import CHECK_CLEAN, LEAKY, evaluate, spec
from tests.support.projects import counter_project, with_declared_size, with_entry
from workers.contract import MIB, ProjectLimits, outcome_of
from workers.evaluation import Evaluator

pytestmark = pytest.mark.browser

COUNTER_TEST = """
module.exports = async (vm, config, cleanup) => {
  const said = [];
  vm.runtime.on('SAY', (target, type, text) => said.push(text));
  vm.greenFlag();
  const deadline = Date.now() + 5000;
  while (!said.includes('done') && Date.now() < deadline) await new Promise(r => setTimeout(r, 20));
  cleanup();
  const count = vm.runtime.getTargetForStage().lookupVariableByNameAndType('count', '').value;
  console.log('count is ' + count);
  return {
    passed_tests: (count === 10 ? 1 : 0) + (said.includes('done') ? 1 : 0), total_tests: 2,
    details: [{name: 'count reaches 10', passed: count === 10, meta: {count}},
              {name: 'says done', passed: said.includes('done')}],
  };
};
"""


async def test_a_passing_project(fresh_evaluator: Evaluator) -> None:
    result = await evaluate(fresh_evaluator, COUNTER_TEST)
    assert result.error is None
    assert (result.success, result.passed, result.total, result.psr) == (True, 2, 2, 1.0)
    assert [t.name for t in result.tests] == ["count reaches 10", "says done"]
    assert result.tests[0].meta == {"count": 10}
    assert "log: count is 10" in result.console
    timings = result.timings
    assert timings.editor_ready_s and timings.project_load_s is not None and timings.script_s is not None
    assert timings.total_s >= timings.editor_ready_s + timings.script_s


async def test_a_partly_passing_project(evaluator: Evaluator) -> None:
    result = await evaluate(evaluator, COUNTER_TEST, counter_project(target=7))
    assert (result.success, result.passed, result.total, result.psr) == (False, 1, 2, 0.5)
    assert result.tests[0].meta == {"count": 7}


async def test_a_throwing_script(evaluator: Evaluator) -> None:
    result = await evaluate(evaluator, "module.exports = async () => { throw new RangeError('boom at case 2'); };")
    assert result.error is not None and result.error.kind == "script_error"
    assert "RangeError: boom at case 2" in result.error.message
    assert (result.success, result.psr, result.tests) == (False, 0.0, [])


@pytest.mark.parametrize(
    ("source", "message"),
    [
        ("module.exports = async (vm => {", "does not parse"),
        ("module.exports = 42;", "must set module.exports to a function, got number"),
        ("throw new Error('at load time');", "threw while loading"),
        ("const x = require('fs'); module.exports = () => ({});", "require('fs') is not available"),
    ],
)
async def test_an_invalid_script(evaluator: Evaluator, source: str, message: str) -> None:
    result = await evaluate(evaluator, source)
    assert result.error is not None and result.error.kind == "script_invalid"
    assert message in result.error.message
    assert "test.js" in result.error.message


async def test_a_broken_helper_is_named(evaluator: Evaluator) -> None:
    result = await evaluate(evaluator, COUNTER_TEST, helper_name="utils.js", helper_source="module.exports = {")
    assert result.error is not None and result.error.kind == "script_invalid"
    assert "utils.js does not parse" in result.error.message


async def test_the_helper_is_installed_under_its_global(evaluator: Evaluator) -> None:
    helper = "module.exports = {answer: () => 42};"
    script = "module.exports = async () => ({details: [{name: 'helper', passed: Helpers.answer() === 42}]});"
    result = await evaluate(evaluator, script, helper_name="h.js", helper_source=helper, helper_global="Helpers")
    assert result.success, result


async def test_a_script_that_never_settles_times_out(evaluator: Evaluator) -> None:
    result = await evaluate(evaluator, "module.exports = () => new Promise(() => {});", timeout_s=1.5)
    assert result.error is not None and result.error.kind == "script_timeout"
    assert "did not finish within 1.5 s" in result.error.message
    assert result.timings.script_s is not None and result.timings.script_s > 1.4  # not before the timeout


async def test_a_script_that_blocks_the_page_is_killed_and_the_session_lives_on(evaluator: Evaluator) -> None:
    result = await evaluate(evaluator, "module.exports = () => { while (true) {} };", timeout_s=1)
    assert result.error is not None and result.error.kind == "script_timeout"
    assert "was killed" in result.error.message
    assert result.timings.script_s is not None and result.timings.script_s >= 1  # killed past its timeout
    after = await evaluate(evaluator, COUNTER_TEST)
    assert after.success, after.error


@pytest.mark.parametrize(
    ("returned", "message"),
    [
        ("'all tests passed'", "returned str"),
        ("undefined", "returned nothing"),
        ("({})", "neither details nor"),
        ("({details: [{name: 'a'}]})", "passed must be true or false"),
        ("({passed_tests: 3, total_tests: 2})", "exceeds"),
    ],
)
async def test_garbage_results(evaluator: Evaluator, returned: str, message: str) -> None:
    result = await evaluate(evaluator, f"module.exports = async () => {returned};")
    assert result.error is not None and result.error.kind == "result_invalid"
    assert message in result.error.message


async def test_cyclic_and_unserialisable_results_survive(evaluator: Evaluator) -> None:
    source = (
        "module.exports = async (vm) => { const meta = {vm: vm.runtime.targets[0].getName(), f: () => 1};"
        " meta.self = meta; return {details: [{name: 'ok', passed: true, meta}]}; };"
    )
    result = await evaluate(evaluator, source)
    assert result.success
    assert result.tests[0].meta == {"vm": "Stage", "self": "[circular]"}


@pytest.mark.parametrize(
    ("data", "message"),
    [
        (b"", "empty"),
        (b"PK\x03\x04 truncated", "not a readable zip"),
        (b"GIF89a", "not an .sb3 zip archive"),
    ],
)
async def test_corrupt_projects_are_refused_before_a_browser_is_spent(
    evaluator: Evaluator, data: bytes, message: str
) -> None:
    result = await evaluate(evaluator, COUNTER_TEST, data)
    assert result.error is not None and result.error.kind == "project_invalid"
    assert message in result.error.message
    assert result.timings.editor_ready_s is None


async def test_projects_over_the_limits_never_reach_a_page(evaluator: Evaluator) -> None:
    bomb = with_declared_size(with_entry(counter_project().to_sb3(), "costume.png", bytes(3 * MIB)), "costume.png", 10)
    result = await evaluator.evaluate(bomb, spec(COUNTER_TEST), ProjectLimits(max_entry_mb=1))
    assert result.error is not None and result.error.kind == "project_too_large"
    assert "'costume.png' inflates past the limit of 1 MiB (project_limits.max_entry_mb)" in result.error.message
    assert result.timings.editor_ready_s is None and result.conditions is None
    assert outcome_of(result) == ("failed", None)  # the agent's project, like one that does not load
    assert (await evaluator.evaluate(counter_project().to_sb3(), spec(COUNTER_TEST), ProjectLimits())).success


async def test_a_project_the_vm_refuses(evaluator: Evaluator) -> None:
    project = json.dumps({"targets": [{"isStage": False, "name": "x"}], "meta": {"semver": "3.0.0"}}).encode()
    result = await evaluate(evaluator, COUNTER_TEST, project)
    assert result.error is not None and result.error.kind == "project_invalid"
    assert "the VM refused the project" in result.error.message


async def test_nothing_leaks_from_one_evaluation_into_the_next(fresh_evaluator: Evaluator) -> None:
    first = await evaluate(fresh_evaluator, LEAKY, counter_project("Other"))
    assert first.success
    second = await evaluate(fresh_evaluator, CHECK_CLEAN, counter_project("Counter"))
    assert second.error is None
    assert [t.name for t in second.tests if not t.passed] == [], second.tests
