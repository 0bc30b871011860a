"""Calibrated frame timing (issue 20, part 3): heavy frames run late in virtual time as they do in Chromium.

The probe counts the VM's frames in two simulated seconds. A project whose every frame calls ~400
blocks and asks for a redraw runs fewer frames under ``calibrated`` timing than under ``ideal``, the
same number on every run; the timing is recorded with the verdict and is part of upstream jobs' identity,
while our suite's job ids stay as they were.
"""

from __future__ import annotations

import itertools
import json
from pathlib import Path

import pytest
from pydantic import ValidationError

from scratchworld_dist import load_suite
from scratchworld_dist._errors import ConfigError
from scratchworld_dist.kinds.tasks import read_task
from scratchworld_dist.kinds.tasks.flakes import FlakeSettings, plan_variants
from scratchworld_dist.sb3 import Project, block, rect_costume
from tests.conftest import REPO
from workers.contract import EvalResult, EvaluationSpec, FrameLateness, calibrated_frame_lateness
from workers.editor import BrowserSession, EditorPool
from workers.evaluation import Evaluator

PROBE = """
module.exports = async (vm) => {
  const runtime = vm.runtime;
  const started = performance.now();
  const frames = [];
  const step = runtime._step;
  runtime._step = function () { frames.push(performance.now() - started); return step.apply(this, arguments); };
  vm.greenFlag();
  await new Promise((resolve) => setTimeout(resolve, 2000));
  runtime._step = step;
  return {details: [{name: 'frames', passed: true, meta: {frames}}]};
};
"""

HEAVY_BLOCKS = 400

# Test coefficients, not the repository's fit: 0.025 ms per block and 2 ms per redraw make a heavy frame
# ~12 ms late (about 22 frames per second instead of 30.3).
LATENESS = FrameLateness(fixed_ms=0.5, per_block_ms=0.025, per_redraw_ms=2)

# The keys of an evaluation spec's JSON under ideal timing (as before timing existed, with the page since),
# in order: job identity hashes this JSON.
SPEC_KEYS_UNDER_IDEAL_TIMING = [
    "script_name",
    "script_source",
    "helper_name",
    "helper_source",
    "helper_global",
    "timeout_s",
    "profile",
    "clock",
    "render",
    "page",
    "config",
]


def heavy() -> bytes:
    """Forever: move (a redraw) and change a variable ``HEAVY_BLOCKS`` times, all in one frame."""
    project = Project()
    project.stage.variable("count", 0)
    body = [block("motion_changexby", DX=1)]
    body += [block("data_changevariableby", VARIABLE="count", VALUE=1) for _ in range(HEAVY_BLOCKS)]
    project.sprite("Dot", costume=rect_costume("dot", 4, 4, "#000000")).script(
        block("event_whenflagclicked"), block("control_forever", SUBSTACK=body)
    )
    return project.to_sb3()


def probe_spec(lateness: FrameLateness | None) -> EvaluationSpec:
    return EvaluationSpec(
        script_name="frames.js",
        script_source=PROBE,
        timeout_s=30,
        clock="virtual",
        timing="calibrated" if lateness else "ideal",
        frame_lateness=lateness,
    )


async def frames(evaluator: Evaluator, lateness: FrameLateness | None) -> tuple[list[float], EvalResult]:
    result = await evaluator.evaluate(heavy(), probe_spec(lateness))
    assert result.error is None, result.error
    return result.tests[0].meta["frames"], result  # type: ignore[index, call-overload]


async def test_heavy_frames_run_late_under_calibrated_timing_the_same_way_every_time(evaluator: Evaluator) -> None:
    ideal, ideal_result = await frames(evaluator, None)
    first, calibrated_result = await frames(evaluator, LATENESS)
    second, _ = await frames(evaluator, LATENESS)
    assert 58 <= len(ideal) <= 62  # 30.3 frames per second
    late_ms = LATENESS.fixed_ms + LATENESS.per_block_ms * HEAVY_BLOCKS + LATENESS.per_redraw_ms
    expected = 2000 / (33 + late_ms)
    assert abs(len(first) - expected) <= 2, (len(first), expected)
    # Frame for frame (times relative to a start that differs per run: equal up to float rounding).
    assert [round(ms, 6) for ms in first] == [round(ms, 6) for ms in second]
    assert ideal_result.conditions is not None and calibrated_result.conditions is not None
    assert (ideal_result.conditions.timing, ideal_result.conditions.frame_lateness) == ("ideal", None)
    assert (calibrated_result.conditions.timing, calibrated_result.conditions.frame_lateness) == (
        "calibrated",
        LATENESS,
    )


async def test_a_page_after_a_calibrated_evaluation_is_reused(session: BrowserSession) -> None:
    """(A pool of its own: an editor of the shared one may retire at its use limit between the two.)"""
    async with EditorPool(session, spare=0) as pool:
        evaluator = Evaluator(session, pool)
        await frames(evaluator, LATENESS)  # the page that ran it recycles into the pool
        ideal, _ = await frames(evaluator, None)
        assert pool.reused == 1 and not pool.discarded
    assert 58 <= len(ideal) <= 62  # no lateness left behind


async def test_the_page_traces_each_frames_work_only_when_asked(evaluator: Evaluator) -> None:
    assert evaluator.pool is not None
    async with evaluator.pool.editor() as editor:
        await editor.load_project(heavy())
        traced = await editor.run_evaluation(probe_spec(None), trace_frames=True)
        await editor.load_project(heavy())
        untraced = await editor.run_evaluation(probe_spec(None))
    assert traced.frames is not None and untraced.frames is None
    clock_ms = [frame[0] for frame in traced.frames]
    assert [round(b - a, 6) for a, b in itertools.pairwise(clock_ms)] == [33] * (len(clock_ms) - 1)
    # Each frame after the first runs the loop body once: the move, the changes and the loop itself.
    assert {frame[2] for frame in traced.frames[1:]} == {HEAVY_BLOCKS + 2}
    assert {frame[3] for frame in traced.frames[1:]} == {1}  # the move asks for a redraw


async def test_the_real_clock_records_its_own_timing(evaluator: Evaluator) -> None:
    spec = probe_spec(None).model_copy(update={"clock": "real", "timeout_s": 10})
    result = await evaluator.evaluate(heavy(), spec)
    assert result.conditions is not None and result.conditions.timing == "real"


def test_calibrated_timing_needs_the_virtual_clock_and_its_coefficients() -> None:
    with pytest.raises(ValidationError, match="model of the virtual clock"):
        EvaluationSpec.model_validate({**probe_spec(LATENESS).model_dump(), "clock": "real"})
    with pytest.raises(ValidationError, match="needs its frame_lateness"):
        EvaluationSpec(script_name="a.js", script_source="", timeout_s=1, clock="virtual", timing="calibrated")
    with pytest.raises(ValidationError, match="only used by calibrated"):
        EvaluationSpec(script_name="a.js", script_source="", timeout_s=1, frame_lateness=LATENESS)


def test_asking_for_calibrated_timing_on_the_real_clock_is_one_clear_error() -> None:
    task = load_suite(REPO / "tasks").select()[0]
    with pytest.raises(ConfigError, match=r"^calibrated frame timing needs the virtual clock"):
        task.evaluation_spec(clock="real", timing="calibrated")


def test_our_suite_keeps_ideal_timing_and_its_job_identity() -> None:
    for task in load_suite(REPO / "tasks").select():
        spec = task.evaluation_spec()
        assert (spec.clock, spec.timing, spec.frame_lateness) == ("virtual", "ideal", None)
        assert list(json.loads(spec.model_dump_json())) == SPEC_KEYS_UNDER_IDEAL_TIMING
    task = load_suite(REPO / "tasks").select()[0]
    assert read_task(task).task_hash == read_task(task, timing="ideal").task_hash
    assert read_task(task).task_hash != read_task(task, timing="calibrated").task_hash


def test_upstream_is_calibrated_in_virtual_time_and_timing_is_part_of_its_identity(fake_clone: Path) -> None:
    task = load_suite(fake_clone).select()[0]
    assert task.evaluation_spec(clock="real").timing == "ideal"  # the real clock has its own
    spec = task.evaluation_spec()  # virtual by default
    assert (spec.timing, spec.frame_lateness) == ("calibrated", calibrated_frame_lateness())
    assert json.loads(spec.model_dump_json())["frame_lateness"] == calibrated_frame_lateness().model_dump()
    calibrated = read_task(task, clock="virtual").task_hash
    assert calibrated != read_task(task, clock="virtual", timing="ideal").task_hash
    assert calibrated == read_task(task, clock="virtual", timing="calibrated").task_hash


def test_the_lateness_axis_also_runs_the_calibrated_model() -> None:
    variants = plan_variants(FlakeSettings(axes=("lateness", "clock"), runs=1), "real", "on_demand", "calibrated")
    assert variants[0].timing == "ideal"  # the real clock has its own
    lateness = [v for v in variants if v.axis == "lateness"]
    assert [v.timing for v in lateness] == ["ideal"] * 5 + ["calibrated"]
    assert [v.timing for v in variants if v.axis == "clock"] == ["calibrated"]  # upstream in virtual time
