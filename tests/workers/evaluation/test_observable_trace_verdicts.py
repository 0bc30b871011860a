"""Recording the observable trace changes no verdict: our suite's projects give the same results with it and without.

Every golden (all pass) and every initial project (none passes every test) of the suite is evaluated as
workers evaluate it, once plainly and once with the trace recorded, under one ``Math.random`` seed:
verdicts, per-test results (names, outcomes, details, virtual durations) and simulated script time
must be identical. The same seed twice gives the same trace.
"""

from __future__ import annotations

import pytest

from scratchworld_dist import load_suite
from scratchworld_dist.suites import Task
from tests.conftest import REPO
from workers.contract import EvalResult, with_random_seed
from workers.evaluation import Evaluator, first_difference

pytestmark = [pytest.mark.browser, pytest.mark.slow]

SUITE = REPO / "tasks"
SEED = 11


def verdict(result: EvalResult) -> tuple[object, ...]:
    """Everything a verdict is made of; wall-clock timings are not."""
    tests = [test.model_dump() for test in result.tests]
    return result.success, result.passed, result.total, result.error, tests, result.timings.script_clock_s


def projects() -> list[object]:
    found = []
    for task in load_suite(SUITE).tasks:
        assert task.golden_project is not None
        for which, path in (("golden", task.golden_project), ("initial", task.initial_project)):
            found.append(pytest.param(task, which, path.read_bytes(), id=f"{task.id}-{which}"))
    return found


@pytest.mark.parametrize(("task", "which", "data"), projects())
async def test_recording_the_trace_changes_no_verdict(
    evaluator: Evaluator, task: Task, which: str, data: bytes
) -> None:
    spec = task.evaluation_spec()
    plain = await evaluator.evaluate(data, with_random_seed(spec, SEED))
    traced = await evaluator.evaluate_traced(data, spec, random_seed=SEED)
    assert verdict(traced.result) == verdict(plain)
    assert plain.success is (which == "golden") and plain.error is None
    assert traced.trace is not None and not traced.trace.truncated and traced.trace.steps > 0
    again = await evaluator.evaluate_traced(data, spec, random_seed=SEED)
    assert again.trace == traced.trace and first_difference(traced.trace, again.trace) is None
