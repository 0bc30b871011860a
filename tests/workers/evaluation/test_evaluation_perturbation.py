"""Perturbed evaluations (``scratchworld flakes``): each perturbation does what it says, and is recorded.

One probe script reports what a perturbation can change: the page's random numbers and the VM's
"pick random", when the VM's first frame comes after the script starts, how many frames a second of
virtual time holds, and where the VM has the mouse.
"""

from __future__ import annotations

import pytest
from pydantic import ValidationError

from scratchworld_dist.sb3 import Project, block, rect_costume
from workers.contract import EvalResult, EvaluationPerturbation, EvaluationSpec, TimerLateness
from workers.evaluation import Evaluator

PROBE = """
module.exports = async (vm) => {
  const runtime = vm.runtime;
  const started = performance.now();
  const frames = [];
  const step = runtime._step;
  runtime._step = function () { frames.push(performance.now() - started); return step.apply(this, arguments); };
  const draws = [Math.random(), Math.random()];
  vm.greenFlag();
  await new Promise((resolve) => setTimeout(resolve, 1000));
  runtime._step = step;
  const stage = runtime.getTargetForStage();
  const picked = Object.values(stage.variables).find((v) => v.name === 'picked').value;
  const mouse = runtime.ioDevices.mouse;
  return {details: [{name: 'probe', passed: true, meta: {
    draws, picked, firstFrameMs: frames[0], framesInASecond: frames.filter((t) => t < 1000).length,
    mouse: typeof mouse._scratchX === 'number' ? [mouse._scratchX, mouse._scratchY] : null,
  }}]};
};
"""


def picker() -> bytes:
    """On the green flag, the stage picks a random number from 1 to 1000000 into ``picked``."""
    project = Project()
    project.stage.variable("picked", 0)
    project.sprite("Dot", costume=rect_costume("dot", 4, 4, "#000000")).script(
        block("event_whenflagclicked"),
        block("data_setvariableto", VARIABLE="picked", VALUE=block("operator_random", FROM=1, TO=1000000)),
    )
    return project.to_sb3()


async def probe(evaluator: Evaluator, perturbation: EvaluationPerturbation | None, clock: str = "virtual") -> dict:
    spec = EvaluationSpec(
        script_name="probe.js", script_source=PROBE, timeout_s=30, clock=clock, perturbation=perturbation
    )
    result: EvalResult = await evaluator.evaluate(picker(), spec)
    assert result.error is None, result.error
    assert result.conditions is not None
    assert result.conditions.perturbation == (perturbation or EvaluationPerturbation(random_seed=0))
    return result.tests[0].meta  # type: ignore[return-value]


@pytest.mark.browser
async def test_the_random_seed_fixes_the_page_and_vm_random_numbers(evaluator: Evaluator) -> None:
    first = await probe(evaluator, EvaluationPerturbation(random_seed=7))
    again = await probe(evaluator, EvaluationPerturbation(random_seed=7))
    other = await probe(evaluator, EvaluationPerturbation(random_seed=8))
    assert (first["draws"], first["picked"]) == (again["draws"], again["picked"])
    assert first["draws"] != other["draws"] and first["picked"] != other["picked"]
    # A run that names no seed draws from seed 0 (the seed before it was undone).
    plain = [(await probe(evaluator, None))["draws"] for _ in range(2)]
    zero = await probe(evaluator, EvaluationPerturbation(random_seed=0))
    assert plain[0] == plain[1] == zero["draws"] and first["draws"] not in plain


@pytest.mark.browser
async def test_the_phase_delays_the_first_frame_and_lateness_slows_the_frame_rate(evaluator: Evaluator) -> None:
    exact = await probe(evaluator, EvaluationPerturbation(random_seed=1))
    assert exact["firstFrameMs"] == 0 and exact["framesInASecond"] in (30, 31)
    shifted = await probe(evaluator, EvaluationPerturbation(random_seed=1, phase_ms=20))
    assert shifted["firstFrameMs"] == 20
    late = await probe(evaluator, EvaluationPerturbation(random_seed=1, lateness=TimerLateness(ms=17)))
    assert late["framesInASecond"] == 20  # one frame per 33 + 17 ms
    jittered = [
        await probe(
            evaluator, EvaluationPerturbation(random_seed=1, lateness=TimerLateness(model="uniform", ms=17, seed=s))
        )
        for s in (3, 3, 4)
    ]
    assert 14 <= jittered[0]["framesInASecond"] <= 26
    assert jittered[0]["framesInASecond"] == jittered[1]["framesInASecond"]  # same seed, same lateness


@pytest.mark.browser
async def test_the_mouse_starts_where_the_perturbation_puts_it(evaluator: Evaluator) -> None:
    placed = await probe(evaluator, EvaluationPerturbation(random_seed=1, mouse=(120, -90)))
    assert placed["mouse"] is not None
    x, y = placed["mouse"]
    assert abs(x - 120) <= 2 and abs(y + 90) <= 2


def test_a_default_spec_dumps_as_before_and_bad_perturbations_are_refused() -> None:
    spec = EvaluationSpec(script_name="a.js", script_source="x", timeout_s=5)
    assert spec.model_dump_json() == (
        '{"script_name":"a.js","script_source":"x","helper_name":null,"helper_source":null,'
        '"helper_global":"EvaluationUtils","timeout_s":5.0,"profile":"native","clock":"real",'
        '"render":"on_demand","page":"bare","config":{}}'
    )
    perturbed = spec.model_copy(update={"perturbation": EvaluationPerturbation(random_seed=3)})
    assert EvaluationSpec.model_validate_json(perturbed.model_dump_json()) == perturbed
    with pytest.raises(ValidationError, match="virtual clock"):
        EvaluationSpec(
            script_name="a.js",
            script_source="x",
            timeout_s=5,
            perturbation=EvaluationPerturbation(random_seed=1, lateness=TimerLateness(ms=4)),
        )
    with pytest.raises(ValidationError, match="virtual clock only"):
        EvaluationSpec(
            script_name="a.js",
            script_source="x",
            timeout_s=5,
            perturbation=EvaluationPerturbation(random_seed=1, phase_ms=3),
        )
    with pytest.raises(ValidationError, match="on the stage"):
        EvaluationPerturbation(random_seed=1, mouse=(300, 0))
