"""Evaluation in virtual time: the same verdicts as real time, errors still classified, real time outside.

The page clock (scratch-gui/clock.js) skips time only while an evaluation script runs. Our whole
suite is compared under both clocks by tests/scratchworld_dist/cli/test_cli.py (``validate``); here a
project made to exercise the timing-sensitive parts of the VM (waits, glides, asks, broadcasts,
clones, touching, sound) is compared, and errors, the clock outside evaluations and job identity
are checked.
"""

from __future__ import annotations

import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest

from scratchworld_dist import load_suite
from scratchworld_dist.kinds.tasks import EpisodeMatrix, plan_jobs, read_task
from tests.conftest import DATA, SUITE_DIR, pooled_editor
from tests.support.projects import counter_project, timing_project
from tests.support.retries import SecondLooks
from workers.contract import EvalResult, EvaluationClock, EvaluationSpec
from workers.editor import EditorPool
from workers.evaluation import Evaluator, wall_limit_s
from workers.evaluation._evaluator import KILL_GRACE_S

pytestmark = pytest.mark.browser

CLOCKS: tuple[EvaluationClock, ...] = ("virtual", "real")


def spec(source: str, clock: EvaluationClock, timeout_s: float = 20, name: str = "test.js") -> EvaluationSpec:
    return EvaluationSpec(script_name=name, script_source=source, timeout_s=timeout_s, clock=clock)


REAL_TRIES = 3
"""Real-clock runs of a reference before a miss counts: its times hold on a quiet machine, but a busy one
delays real timers and frames (an answer given 30 ms after its question was seen after 590 ms in one CI
run, against a window of 30-300 ms). Every further run is reported in the run's summary (``second_looks``).
The virtual run, the one under test, gets one try."""


TOOK_TOLERANCE_MS = 150
"""How far apart the two clocks may see the pong game end (a few frames)."""


async def under_both_clocks(
    evaluator: Evaluator,
    project: bytes,
    source: str,
    name: str,
    undelayed: Callable[[EvalResult, EvalResult], bool],
    second_looks: SecondLooks,
) -> dict[EvaluationClock, EvalResult]:
    """The virtual run once; the real reference up to ``REAL_TRIES`` times, until ``undelayed(virtual, real)``
    says load did not delay it (the caller then asserts on the last real run either way). Each real run
    after the first is a reported second look."""
    results: dict[EvaluationClock, EvalResult] = {
        "virtual": await evaluator.evaluate(project, spec(source, "virtual", name=name))
    }
    for attempt in range(REAL_TRIES):
        if attempt:
            seen = [(t.name, t.passed, t.meta) for t in results["real"].tests]
            second_looks.took(name, f"real-clock run {attempt} looked delayed: {seen}")
        results["real"] = await evaluator.evaluate(project, spec(source, "real", name=name))
        if undelayed(results["virtual"], results["real"]):
            break
    return results


async def test_timing_sensitive_blocks_behave_alike_under_both_clocks(
    evaluator: Evaluator, second_looks: SecondLooks
) -> None:
    source = (DATA / "clock_behaviours.js").read_text()
    results = await under_both_clocks(
        evaluator, timing_project(), source, "clock_behaviours.js", lambda _, real: real.success, second_looks
    )
    for clock, result in results.items():
        assert result.error is None, (clock, result.error)
        assert [t.name for t in result.tests if not t.passed] == [], (clock, [t for t in result.tests if not t.passed])
        assert result.conditions is not None and result.conditions.clock == clock
    virtual, real = results["virtual"], results["real"]
    assert [t.passed for t in virtual.tests] == [t.passed for t in real.tests]
    # The virtual run simulated as many seconds as the real one took, in much less wall time.
    assert virtual.timings.script_clock_s is not None and real.timings.script_clock_s is not None
    assert virtual.timings.script_clock_s == pytest.approx(real.timings.script_clock_s, rel=0.25)
    assert virtual.timings.script_s is not None and virtual.timings.script_s < virtual.timings.script_clock_s


@pytest.fixture
def busy_core() -> Iterator[subprocess.Popen[bytes]]:
    """Another process spinning on one of the machine's cores (until the test kills it)."""
    hog = subprocess.Popen([sys.executable, "-c", "while True: pass"])
    try:
        yield hog
    finally:
        hog.kill()
        hog.wait()


async def test_a_busy_core_changes_nothing_in_virtual_time(
    evaluator: Evaluator, busy_core: subprocess.Popen[bytes]
) -> None:
    """Time stands still while the page computes, so load slows an evaluation down but cannot move
    an event to another frame: the measured times are the same to the millisecond."""
    source = (DATA / "clock_behaviours.js").read_text()
    project = timing_project()
    loaded = await evaluator.evaluate(project, spec(source, "virtual", name="clock_behaviours.js"))
    assert loaded.error is None and [t.name for t in loaded.tests if not t.passed] == [], loaded.tests
    busy_core.kill()
    busy_core.wait()
    idle = await evaluator.evaluate(project, spec(source, "virtual", name="clock_behaviours.js"))
    assert [(t.name, t.passed, t.meta) for t in loaded.tests] == [(t.name, t.passed, t.meta) for t in idle.tests]


async def test_a_hanging_and_a_throwing_script_are_classified_in_virtual_time(evaluator: Evaluator) -> None:
    project = counter_project().to_sb3()
    hung = await evaluator.evaluate(project, spec("module.exports = () => new Promise(() => {});", "virtual", 10))
    assert hung.error is not None and hung.error.kind == "script_timeout"
    assert "did not finish within 10 s of virtual time" in hung.error.message
    # The ten simulated seconds the message names were skipped: they took less wall time than that.
    assert hung.timings.script_s is not None and hung.timings.script_s < 10

    thrown = await evaluator.evaluate(
        project,
        spec(
            "module.exports = async () => { await new Promise(r => setTimeout(r, 5000)); throw new Error('late'); };",
            "virtual",
        ),
    )
    assert thrown.error is not None and thrown.error.kind == "script_error"
    assert "Error: late" in thrown.error.message

    # A script that blocks the page is killed as in real time, after twice the timeout (virtual time
    # can run slower than real time on heavy frames) plus the grace (test_evaluation.py).
    assert wall_limit_s(10, "virtual") == 2 * 10 + KILL_GRACE_S
    assert wall_limit_s(10, "real") == 10 + KILL_GRACE_S


WAIT_A_SECOND = """module.exports = async () => {
  const started = Date.now();
  await new Promise((resolve) => setTimeout(resolve, 1000));
  return {details: [{name: 'waited', passed: true, meta: {ms: Date.now() - started}}]};
};"""


async def test_the_clock_is_real_outside_an_evaluation(shared_pool: EditorPool) -> None:
    async with pooled_editor(shared_pool) as editor:
        before = await editor.clock_status()
        assert before["mode"] == "real" and before["offsetMs"] == 0
        assert abs(before["dateNow"] - before["realDateNow"]) < 50  # type: ignore[operator]
        assert before["now"] == pytest.approx(before["realNow"], abs=50)
        await editor.load_project(counter_project().to_sb3())

        # A virtual evaluation: ten simulated seconds in a fraction of the wall time.
        started = time.perf_counter()
        run = await editor.run_evaluation(spec(WAIT_A_SECOND.replace("1000", "10000"), "virtual"))
        real_ms = (time.perf_counter() - started) * 1000
        assert 10_000 <= run.duration_ms < 10_100
        assert real_ms < run.duration_ms  # the simulated seconds went faster than real ones

        # Back to real time: the clock moves on at real speed, ahead by the ten virtual seconds less
        # the real time the evaluation took (however loaded the machine).
        after = await editor.clock_status()
        assert after["mode"] == "real"
        assert 10_000 - real_ms <= after["offsetMs"] < 10_100  # type: ignore[operator]
        started = time.perf_counter()
        run = await editor.run_evaluation(spec(WAIT_A_SECOND, "real"))
        assert time.perf_counter() - started >= 1.0
        assert run.duration_ms >= 1000


def test_the_clock_is_part_of_a_jobs_identity_and_suites_pick_their_default(fake_clone: Path) -> None:
    task = load_suite(SUITE_DIR).tasks[0]
    assert task.evaluation_spec().clock == "virtual"
    assert task.evaluation_spec(clock="real").clock == "real"
    assert load_suite(fake_clone).tasks[0].evaluation_spec().clock == "virtual"
    ids = {
        clock: next(
            iter(
                plan_jobs(
                    EpisodeMatrix(
                        models=[None],
                        modes=["composite"],
                        agent="oracle",
                        tasks=[read_task(task, clock=clock)],
                        seeds=[0],
                        max_steps=50,
                    )
                )
            )
        ).job_id
        for clock in CLOCKS
    }
    assert ids["virtual"] != ids["real"]


def took_ms(result: EvalResult) -> float | None:
    """The pong probe's time from the green flag to the game's end, when it got that far."""
    meta = result.tests[1].meta if len(result.tests) > 1 else None
    took = meta.get("took") if isinstance(meta, dict) else None
    return float(took) if isinstance(took, int | float) else None


@pytest.mark.upstream
async def test_an_upstream_game_runs_frame_for_frame_alike_under_both_clocks(
    evaluator: Evaluator, upstream_dir: Path, second_looks: SecondLooks
) -> None:
    """Upstream's pong golden (forever loops, touching a colour, sounds, stop all) with a probe of ours."""
    project = (upstream_dir / "scratch-gui" / "static" / "pong_starter_golden.sb3").read_bytes()
    source = (DATA / "pong_probe.js").read_text()

    def undelayed(virtual: EvalResult, real: EvalResult) -> bool:  # (one CI run: 1081 ms against 925)
        virtual_took, real_took = took_ms(virtual), took_ms(real)
        return virtual_took is None or real_took is None or abs(real_took - virtual_took) <= TOOK_TOLERANCE_MS

    results = await under_both_clocks(evaluator, project, source, "pong_probe.js", undelayed, second_looks)
    metas = {}
    for clock, result in results.items():
        assert result.error is None and result.success, (clock, result)
        metas[clock] = result.tests[1].meta
    virtual, real = metas["virtual"], metas["real"]
    assert isinstance(virtual, dict) and isinstance(real, dict)
    assert (virtual["frames"], virtual["x"], virtual["y"]) == (real["frames"], real["x"], real["y"])
    assert virtual["took"] == pytest.approx(real["took"], abs=TOOK_TOLERANCE_MS)
