"""Evaluation profiles: the stage canvas and mouse state a script sees are set, checked and recorded."""

from __future__ import annotations

from pathlib import Path

import pytest

from scratchworld_dist.kinds.tasks import EpisodeMatrix, plan_jobs, read_task
from scratchworld_dist.suites import load_suite
from tests.conftest import SUITE_DIR
from tests.support.projects import counter_project
from workers.contract import EvaluationSpec
from workers.evaluation import Evaluator

pytestmark = pytest.mark.browser

# Reports what the page looks like to an evaluation script, as tests whose names carry the values.
PROBE = """module.exports = async (vm) => {
  const canvas = vm.renderer.gl.canvas;
  const mouse = vm.runtime.ioDevices.mouse;
  const seen = [`canvas ${canvas.width}x${canvas.height}`, `mouse ${typeof mouse._scratchX === 'number'
    ? Math.round(mouse.getScratchX()) + ',' + Math.round(mouse.getScratchY()) : 'unknown'}`,
    `dpr ${window.devicePixelRatio}`];
  return {passed: seen.length, total: seen.length, details: seen.map((name) => ({name, passed: true}))};
};"""


@pytest.mark.parametrize(
    ("profile", "seen"),
    [
        ("native", ["canvas 480x360", "mouse unknown", "dpr 1"]),
        ("upstream", ["canvas 240x180", "mouse 0,0", "dpr 1"]),
    ],
)
async def test_a_script_sees_the_profile(evaluator: Evaluator, profile: str, seen: list[str]) -> None:
    spec = EvaluationSpec(script_name="probe.js", script_source=PROBE, timeout_s=20, profile=profile)
    result = await evaluator.evaluate(counter_project().to_sb3(), spec)
    assert result.error is None, result.error
    assert [test.name for test in result.tests] == seen
    assert result.conditions is not None
    assert result.conditions.profile == profile
    assert result.conditions.stage_canvas == ((480, 360) if profile == "native" else (240, 180))
    assert result.conditions.device_pixel_ratio == 1
    assert result.conditions.mouse_known is (profile == "upstream")


def test_suites_pick_their_default_profile(fake_clone: Path) -> None:
    ours = load_suite(SUITE_DIR).tasks[0]
    assert ours.evaluation_spec().profile == "native"
    assert ours.evaluation_spec("upstream").profile == "upstream"
    upstream = load_suite(fake_clone).tasks[0]
    assert upstream.default_profile == "upstream"
    assert upstream.evaluation_spec().profile == "upstream"


def test_the_profile_is_part_of_a_jobs_identity() -> None:
    task = load_suite(SUITE_DIR).tasks[0]
    ids = {
        profile: next(
            iter(
                plan_jobs(
                    EpisodeMatrix(
                        models=[None],
                        modes=["composite"],
                        agent="oracle",
                        tasks=[read_task(task, profile)],
                        seeds=[0],
                        max_steps=50,
                    )
                )
            )
        ).job_id
        for profile in ("native", "upstream")
    }
    assert ids["native"] != ids["upstream"]
    assert (
        next(
            iter(
                plan_jobs(
                    EpisodeMatrix(
                        models=[None],
                        modes=["composite"],
                        agent="oracle",
                        tasks=[read_task(task)],
                        seeds=[0],
                        max_steps=50,
                    )
                )
            )
        ).job_id
        == ids["native"]
    )
