"""From a flake run's evaluations to each test's stability: rate, flipping perturbations, frame-rate band.

A test is unstable when its verdict is not the same in every run of its project. A failed
evaluation (no report) counts as the verdict ``error`` for each of the project's tests, and a test
that a run did not report as ``missing``, so that neither hides a flip.
"""

from __future__ import annotations

from pydantic import BaseModel

from scratchworld_dist._validation import Which
from scratchworld_dist.kinds.tasks.flakes._plan import Axis, FlakeSettings
from scratchworld_dist.kinds.tasks.flakes._runner import ERROR_VERDICT, FlakeRun
from workers.contract import EvaluationClock, EvaluationPage, EvaluationProfile, EvaluationRender, frames_per_second

EVALUATION_TEST = "(evaluation)"
"""The one test of a project none of whose runs produced a report."""


class Flip(BaseModel):
    """A run whose verdict on a test differs from the baseline's."""

    axis: Axis
    label: str
    verdict: str


class LatenessBand(BaseModel):
    """Where a test passes on the lateness axis: the levels, and the frame rates they give."""

    passes_ms: list[float]
    fails_ms: list[float]
    min_fps: float | None
    """The lowest frame rate at which it passes (None: it passes at no level)."""
    max_fps: float | None
    calibrated: str | None = None
    """The verdict under the calibrated frame timing (None: not run)."""
    depends_on_timing: bool | None = None
    """Whether the verdict under calibrated timing differs from the one at 0 ms on ideal timing (None: one
    of the two was not run): a test that does depends on the lateness model at all."""

    def describe(self) -> str:
        """The band for people: the frame rates where it passes, and its verdict under calibrated timing."""
        if self.min_fps is None:
            text = "passes at no lateness"
        elif not self.fails_ms:
            text = f"all ({self.min_fps:g}-{self.max_fps:g} fps)"
        else:
            fails = ", ".join(f"{ms:g}" for ms in self.fails_ms)
            text = f"{self.min_fps:g}-{self.max_fps:g} fps (fails at {fails} ms)"
        if self.calibrated is not None:
            text += f"; calibrated: {self.calibrated}{' (depends on frame timing)' if self.depends_on_timing else ''}"
        return text


class TestStability(BaseModel):
    """One test of one project over all runs of a flake run."""

    __test__ = False  # not a pytest test class, despite the name

    task_id: str
    category: str
    which: Which
    test: str
    stable: bool
    baseline: str
    """The verdict in the baseline run: ``pass``, ``fail``, ``error`` or ``missing``."""
    runs: int
    flipped: int
    """Runs (besides the baseline) whose verdict differs from the baseline's."""
    rate: float
    """``flipped`` over the runs besides the baseline."""
    rate_by_axis: dict[str, float]
    flips: list[Flip]
    lateness_band: LatenessBand | None
    """None when the lateness axis did not run."""
    blocking: bool
    """Unstable, and of a golden or a debug task's initial: the suite is not fit to score with."""


class FlakeConditions(BaseModel):
    """The baseline's conditions, shared by the runs that do not vary them."""

    profile: EvaluationProfile
    clock: EvaluationClock
    render: EvaluationRender
    page: EvaluationPage = "editor"
    """The page every run used (reports made before the bare page existed: the editor)."""


class FlakeReport(BaseModel):
    """What ``scratchworld flakes`` writes as JSON."""

    suite: str
    conditions: FlakeConditions
    settings: FlakeSettings
    evaluations: int
    unstable: int
    blocking: int
    tests: list[TestStability]
    runs: list[FlakeRun]


def _verdict(run: FlakeRun, test: str) -> str:
    if run.error is not None:
        return ERROR_VERDICT
    if test not in run.verdicts:
        return "missing"
    return "pass" if run.verdicts[test] else "fail"


def _band(runs: list[FlakeRun], test: str) -> LatenessBand | None:
    passes, fails = [], []
    ideal: str | None = None
    calibrated: str | None = None
    for run in runs:
        if run.variant.axis != "lateness":
            continue
        if run.variant.timing == "calibrated":
            calibrated = _verdict(run, test)
        elif run.variant.perturbation.lateness is not None:
            ms = run.variant.perturbation.lateness.ms
            (passes if _verdict(run, test) == "pass" else fails).append(ms)
            if ms == 0:
                ideal = _verdict(run, test)
    if not passes and not fails and calibrated is None:
        return None
    return LatenessBand(
        passes_ms=sorted(passes),
        fails_ms=sorted(fails),
        min_fps=round(frames_per_second(max(passes)), 1) if passes else None,
        max_fps=round(frames_per_second(min(passes)), 1) if passes else None,
        calibrated=calibrated,
        depends_on_timing=None if ideal is None or calibrated is None else ideal != calibrated,
    )


def stability_of_tests(runs: list[FlakeRun]) -> list[TestStability]:
    """Each test of each project, in the order the runs list the projects; runs start with each project's baseline."""
    by_project: dict[tuple[str, Which], list[FlakeRun]] = {}
    for run in runs:
        by_project.setdefault((run.task_id, run.which), []).append(run)
    rows = []
    for project_runs in by_project.values():
        baseline = next((run for run in project_runs if run.variant.axis == "baseline"), None)
        if baseline is None:
            raise ValueError(f"no baseline run of {project_runs[0].task_id} {project_runs[0].which}")
        names = list(dict.fromkeys(name for run in project_runs for name in run.verdicts)) or [EVALUATION_TEST]
        others = [run for run in project_runs if run is not baseline]
        for name in names:
            expected = _verdict(baseline, name)
            flips = [
                Flip(axis=run.variant.axis, label=run.variant.label, verdict=_verdict(run, name))  # type: ignore[arg-type]
                for run in others
                if _verdict(run, name) != expected
            ]
            per_axis: dict[str, list[int]] = {}
            for run in others:
                counts = per_axis.setdefault(run.variant.axis, [0, 0])
                counts[0] += _verdict(run, name) != expected
                counts[1] += 1
            stable = not flips
            blocking = not stable and (baseline.which == "golden" or baseline.category == "debug")
            rows.append(
                TestStability(
                    task_id=baseline.task_id,
                    category=baseline.category,
                    which=baseline.which,
                    test=name,
                    stable=stable,
                    baseline=expected,
                    runs=len(project_runs),
                    flipped=len(flips),
                    rate=round(len(flips) / len(others), 3) if others else 0.0,
                    rate_by_axis={axis: round(bad / total, 3) for axis, (bad, total) in per_axis.items()},
                    flips=flips,
                    lateness_band=_band(project_runs, name),
                    blocking=blocking,
                )
            )
    return rows
