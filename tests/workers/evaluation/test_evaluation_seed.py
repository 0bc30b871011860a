"""Seeded verdicts: every evaluation of a job, and its agent's page, draw ``Math.random`` from a seed made of
the job's task and sweep seed, so that a rerun anywhere repeats the verdict, and the seed is recorded with it.
"""

from __future__ import annotations

import io
import json
import zipfile

import pytest

from tests.conftest import pooled_editor
from tests.workers.evaluation.test_evaluation_perturbation import PROBE, picker
from workers.contract import MAX_SEED, BridgeError, EvalResult, EvaluationSpec, evaluation_seed, with_random_seed
from workers.editor import Editor, EditorPool
from workers.evaluation import Evaluator


def test_the_seed_is_the_task_and_sweep_seed_s_alone() -> None:
    seeds = {evaluation_seed(task, seed) for task in ("a", "b", "sum_two_numbers") for seed in range(4)}
    assert len(seeds) == 12 and all(0 <= s <= MAX_SEED for s in seeds)
    assert evaluation_seed("a", 1) == evaluation_seed("a", 1)


def test_a_seed_out_of_range_is_refused_in_one_line() -> None:
    spec = EvaluationSpec(script_name="probe.js", script_source=PROBE, timeout_s=30)
    with pytest.raises(ValueError, match=r"a random seed is from 0 to 4294967295, got -1"):
        with_random_seed(spec, -1)


# A verdict that depends on the random numbers: the VM's pick decides the test.
COIN = """
module.exports = async (vm) => {
  vm.greenFlag();
  await new Promise((resolve) => setTimeout(resolve, 200));
  const picked = Object.values(vm.runtime.getTargetForStage().variables).find((v) => v.name === 'picked').value;
  return {details: [{name: 'heads', passed: Number(picked) <= 500000, meta: {picked}}]};
};
"""


@pytest.mark.browser
async def test_a_random_verdict_repeats_under_its_seed_and_the_seeds_sample_both(evaluator: Evaluator) -> None:
    spec = EvaluationSpec(script_name="coin.js", script_source=COIN, timeout_s=30, clock="virtual")
    verdicts: dict[int, bool] = {}
    for seed in range(6):
        seeded = with_random_seed(spec, evaluation_seed("coin", seed))
        first: EvalResult = await evaluator.evaluate(picker(), seeded)
        again = await evaluator.evaluate(picker(), seeded)
        assert first.tests[0].meta == again.tests[0].meta and first.success == again.success
        assert first.random_seed == evaluation_seed("coin", seed)
        verdicts[seed] = first.success
    assert set(verdicts.values()) == {True, False}, verdicts  # six seeds: both sides of a fair coin


@pytest.mark.browser
async def test_a_spec_without_a_seed_draws_from_seed_zero(evaluator: Evaluator) -> None:
    spec = EvaluationSpec(script_name="probe.js", script_source=PROBE, timeout_s=30, clock="virtual")
    plain = await evaluator.evaluate(picker(), spec)
    zero = await evaluator.evaluate(picker(), with_random_seed(spec, 0))
    assert plain.random_seed == 0
    assert plain.tests[0].meta == zero.tests[0].meta


GREEN_FLAG = '[class*="green-flag_green-flag"]'


async def picked_on_the_flag(editor: Editor, seed: int | None) -> str:
    """``picker``'s number after a click on the editor's green flag (as a primitive agent clicks it), the page
    seeded with ``seed`` after the load as an episode's is (None: not seeded)."""
    await editor.load_project(picker())
    if seed is not None:
        await editor.seed_random(seed)
    await editor.page.click(GREEN_FLAG)
    for _ in range(200):  # the VM sets it on its next frame; the saved project shows it
        with zipfile.ZipFile(io.BytesIO(await editor.save_project())) as archive:
            stage = json.loads(archive.read("project.json"))["targets"][0]
        (value,) = [value for name, value in stage["variables"].values() if name == "picked"]
        if str(value) != "0":
            return str(value)
    raise AssertionError("the green flag never ran the picker")


@pytest.mark.browser
async def test_the_agent_page_draws_from_its_seed_until_it_is_recycled(shared_pool: EditorPool) -> None:
    async with pooled_editor(shared_pool) as editor:
        first = await picked_on_the_flag(editor, 11)
        again = await picked_on_the_flag(editor, 11)
        other = await picked_on_the_flag(editor, 12)
        assert first == again and first != other
        assert await editor.recycle() == []  # the seed undone, nothing else left behind
        await editor.resume()
        unseeded = {await picked_on_the_flag(editor, None) for _ in range(2)}
        assert len(unseeded) == 2 and first not in unseeded


@pytest.mark.browser
async def test_a_seed_the_bridge_cannot_use_is_refused(shared_pool: EditorPool) -> None:
    async with pooled_editor(shared_pool) as editor:
        with pytest.raises(BridgeError, match="seed must be an integer from 0 to 2"):
            await editor.seed_random(-3)
