"""A traced run reused (``evaluate_traced(..., reuse=True)``, the audit's golden beside each misjudged variant):
the same bytes under the same spec, seed, limits and cap give the run kept, without a page; anything else that
differs, or a caller that does not ask, runs again; a run with no trace is never kept."""

from __future__ import annotations

import pytest

from tests.support.projects import counter_project
from workers.contract import EvaluationSpec, ProjectLimits
from workers.editor import BrowserSession, EditorPool
from workers.evaluation import Evaluator

pytestmark = pytest.mark.browser

SAY_COUNT = """
module.exports = async (vm) => {
  vm.greenFlag();
  await new Promise((resolve) => setTimeout(resolve, 500));
  return {details: [{name: 'ran', passed: true}]};
};
"""

SPEC = EvaluationSpec(script_name="say.js", script_source=SAY_COUNT, timeout_s=20, clock="virtual")


async def test_a_traced_run_is_reused_only_for_the_same_run(session: BrowserSession, shared_pool: EditorPool) -> None:
    evaluator = Evaluator(session, shared_pool)  # a memo of its own, the shared pages
    golden, other = counter_project(target=10).to_sb3(), counter_project(target=7).to_sb3()
    opened = shared_pool.reused + shared_pool.opened
    first = await evaluator.evaluate_traced(golden, SPEC, random_seed=0, reuse=True)
    assert first.trace is not None and first.result.success
    assert await evaluator.evaluate_traced(golden, SPEC, random_seed=0, reuse=True) is first
    assert shared_pool.reused + shared_pool.opened == opened + 1 and evaluator.traced_runs.reused == 1
    again = [
        await evaluator.evaluate_traced(golden, SPEC, random_seed=0),  # not asked to reuse
        await evaluator.evaluate_traced(golden, SPEC, random_seed=1, reuse=True),
        await evaluator.evaluate_traced(golden, SPEC, random_seed=0, max_chars=50_000, reuse=True),
        await evaluator.evaluate_traced(other, SPEC, random_seed=0, reuse=True),
        await evaluator.evaluate_traced(golden, SPEC.model_copy(update={"timeout_s": 30}), random_seed=0, reuse=True),
    ]
    assert all(run is not first and run.trace is not None for run in again)
    assert shared_pool.reused + shared_pool.opened == opened + 1 + len(again) and evaluator.traced_runs.reused == 1
    assert again[0].trace == first.trace  # reproducible: what makes a kept run as good as a new one


async def test_a_run_without_a_trace_is_not_kept(evaluator: Evaluator) -> None:
    refused = counter_project().to_sb3()
    tight = ProjectLimits(max_file_mb=0.0001)
    runs = [await evaluator.evaluate_traced(refused, SPEC, tight, random_seed=0, reuse=True) for _ in range(2)]
    assert all(run.trace is None and run.result.error is not None for run in runs) and runs[0] is not runs[1]
