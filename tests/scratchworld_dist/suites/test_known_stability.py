"""A suite's known test stability: written from a flake report, read back, and used where users meet verdicts."""

from __future__ import annotations

from pathlib import Path

import pytest

from scratchworld_dist import results
from scratchworld_dist._errors import SuiteError
from scratchworld_dist._validation import ProjectCheck, TaskValidation
from scratchworld_dist.kinds.tasks.flakes import (
    FlakeConditions,
    FlakeReport,
    FlakeRun,
    FlakeSettings,
    plan_variants,
    stability_of_tests,
    suite_stability,
)
from scratchworld_dist.suites import (
    SuiteStability,
    UpstreamSuiteLoader,
    known_stability,
    load_suite,
    stability_file,
    stability_marks,
)
from scratchworld_dist.suites._stability import PACKAGED_DIR
from tests.conftest import SUITE_DIR
from tests.support.small_suites import TASK, native_suite, upstream_clone
from workers.contract import EvalResult, TestVerdict

SETTINGS = FlakeSettings(runs=1, axes=("phase", "lateness"), lateness_ms=(0, 25))


def _report(suite_name: str, task_id: str) -> FlakeReport:
    """A flake run of one task whose golden test ``late`` fails at 25 ms lateness; ``steady`` never flips."""
    variants = plan_variants(SETTINGS, "virtual", "on_demand")
    runs = []
    for variant in variants:
        late = variant.perturbation.lateness is not None and variant.perturbation.lateness.ms == 25
        for which, verdicts in (("golden", {"late": not late, "steady": True}), ("initial", {"late": False})):
            runs.append(
                FlakeRun(
                    task_id=task_id,
                    category="compute",
                    which=which,  # type: ignore[arg-type]
                    variant=variant,
                    verdicts=verdicts,
                    error=None,
                    load_average=0.1,
                    wall_s=0.2,
                )
            )
    rows = stability_of_tests(runs)
    return FlakeReport(
        suite=suite_name,
        conditions=FlakeConditions(profile="native", clock="virtual", render="on_demand", page="bare"),
        settings=SETTINGS,
        evaluations=len(runs),
        unstable=sum(not row.stable for row in rows),
        blocking=sum(row.blocking for row in rows),
        tests=rows,
        runs=runs,
    )


@pytest.fixture
def suite_root(tmp_path: Path) -> Path:
    native_suite(tmp_path / "suite")
    return tmp_path / "suite"


def _write_findings(suite_root: Path) -> SuiteStability:
    suite = load_suite(suite_root)
    found = suite_stability(_report(suite.name, TASK), suite.tasks, "scratchworld flakes suite")
    stability_file(suite).write_text(found.model_dump_json(indent=2), encoding="utf-8")
    return found


def test_findings_name_each_unstable_test_with_what_flipped_it_and_its_band(suite_root: Path) -> None:
    found = _write_findings(suite_root)
    suite = load_suite(suite_root)
    assert known_stability(suite) == found
    assert found.tests_checked == 2 and list(found.scripts) == [TASK]
    (late,) = found.unstable
    assert (late.task_id, late.test, late.projects, late.flipped_by) == (TASK, "late", ["golden"], ["lateness"])
    assert late.flips == ["golden: lateness 25 ms (17.2 fps) → fail"]
    assert late.passes_at is not None and late.passes_at.startswith("golden 30.3-30.3 fps (fails at 25 ms)")
    assert late.note().startswith("unstable: lateness changed it in 1 of")
    (task,) = suite.tasks
    assert set(found.unstable_tests(task) or {}) == {"late"}


def test_a_task_whose_script_changed_since_is_no_longer_covered(suite_root: Path) -> None:
    _write_findings(suite_root)
    script = suite_root / "compute" / TASK / "evaluate.js"
    script.write_text(script.read_text() + "\n// changed\n")
    suite = load_suite(suite_root)
    known = known_stability(suite)
    assert known is not None
    (task,) = suite.tasks
    assert known.standing(task) == "changed" and known.unstable_tests(task) is None
    marks = stability_marks(suite, suite.tasks)
    assert marks is not None and marks.checked == [] and marks.is_unstable(TASK, "late") is None


def test_a_suite_without_findings_has_none_and_a_malformed_file_is_named(suite_root: Path) -> None:
    suite = load_suite(suite_root)
    assert known_stability(suite) is None and stability_marks(suite, suite.tasks) is None
    stability_file(suite).write_text('{"suite": 1}')
    with pytest.raises(SuiteError, match=r"stability\.json: not a test stability file"):
        known_stability(load_suite(suite_root))


def test_an_upstream_clone_reads_the_data_shipped_with_the_package(tmp_path: Path) -> None:
    suite = load_suite(upstream_clone(tmp_path / "clone"))
    assert stability_file(suite) == PACKAGED_DIR / "upstream.json"
    known = known_stability(suite)
    assert known is not None and known.profile == "upstream" and len(known.scripts) >= 67
    (task,) = suite.tasks  # not an upstream task: the data does not cover it
    assert known.standing(task) == "unchecked" and known.unstable_tests(task) is None


def test_test_rows_carry_the_runs_marks(suite_root: Path) -> None:
    _write_findings(suite_root)
    suite = load_suite(suite_root)
    marks = stability_marks(suite, suite.tasks)
    assert marks is not None and marks.unstable == {TASK: {"late": marks.unstable[TASK]["late"]}}
    result = EvalResult(
        success=False,
        passed=1,
        total=2,
        psr=0.5,
        tests=[TestVerdict(name="late", passed=False), TestVerdict(name="steady", passed=True)],
    )
    rows = results.test_rows("job", 0, TASK, result, marks)
    assert [(row.name, row.unstable) for row in rows] == [("late", True), ("steady", False)]
    assert [row.unstable for row in results.test_rows("job", 0, "other_task", result, marks)] == [None, None]


def _check(passed: bool, failed: list[str]) -> ProjectCheck:
    total = len(failed) + 1
    return ProjectCheck(
        success=passed,
        passed=total - len(failed),
        total=total,
        psr=(total - len(failed)) / total,
        error=None,
        wall_s=1.0,
        failed_tests=failed,
    )


def test_validate_warns_instead_of_failing_when_a_golden_fails_only_unstable_tests() -> None:
    initial = _check(False, ["late", "steady"])
    row = TaskValidation(
        task_id=TASK, category="compute", golden=_check(False, ["late"]), initial=initial, unstable_tests={"late": "x"}
    )
    assert row.failures() == [] and row.warnings() == ["golden fails only unstable test(s) 'late'"]
    also_stable = row.model_copy(update={"golden": _check(False, ["late", "steady"])})
    assert also_stable.failures() == ["golden does not pass"]
    unknown = row.model_copy(update={"unstable_tests": None})
    assert unknown.failures() == ["golden does not pass"]


def test_our_suite_keeps_its_known_stability_current() -> None:
    """A task whose script changes must be checked again: the failure says how."""
    suite = load_suite(SUITE_DIR)
    known = known_stability(suite)
    assert known is not None, f"{stability_file(suite)} is missing: make it with scratchworld flakes --stability-out"
    stale = [task.id for task in suite.tasks if known.standing(task) != "checked"]
    assert not stale, f"{stale} changed since {known.made_on}: regenerate with {known.command}"


@pytest.mark.upstream
def test_the_shipped_upstream_data_covers_every_task_whose_script_is_in_shared(upstream_dir: Path) -> None:
    suite = UpstreamSuiteLoader(require_scripts=False).load(upstream_dir)
    with_scripts = [task for task in suite.tasks if task.evaluation_script.is_file()]
    if not with_scripts:
        pytest.skip(f"no evaluation scripts under {upstream_dir}")
    known = known_stability(suite)
    assert known is not None
    assert [task.id for task in with_scripts if known.standing(task) != "checked"] == []


def test_a_runs_plan_carries_the_marks_of_its_tasks_and_our_demo_knows_every_task_stable() -> None:
    from scratchworld_dist._run import plan_run
    from scratchworld_dist.sweep import load_sweep_config

    plan = plan_run(load_sweep_config(SUITE_DIR.parent / "configs" / "demo.yaml"))
    marks = plan.suite.stability
    assert marks is not None and marks.source.endswith("tasks/stability.json")
    assert sorted(marks.checked) == sorted(task.id for task in load_suite(SUITE_DIR).tasks)
    assert marks.unstable == {} and marks.is_unstable(marks.checked[0], "any test") is False
