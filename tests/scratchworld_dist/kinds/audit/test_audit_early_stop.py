"""The audit's mutants stop at their first failing test (``audit.stop_at_first_kill``, on by default): only
mutants are judged that way, the option is part of their jobs' identity (and of nothing else's), the worker is
told it, and a killed mutant's row names the test that killed it and how many did not run."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from scratchworld_dist.kinds.audit._panel import variant_panel
from scratchworld_dist.kinds.audit._remake import ProgramsUnavailableError, remade_programs
from scratchworld_dist.kinds.audit._rows import audit_row
from scratchworld_dist.results import SCHEMA_VERSION, RunManifest, write_manifest
from scratchworld_dist.sweep import JobSpec, plan_run, sweep_config_from, worker_job
from tests.conftest import SUITE_DIR
from workers.contract import EarlyStop, EvalResult, EvaluationSpec, JobResult, TestVerdict
from workers.kinds.audit import AuditSpec

TASK = "arrow_key_walker"


def planned(tmp_path: Path, **section: Any) -> dict[tuple[str, str], JobSpec]:
    """The audit's jobs for one task of our suite, by (variant kind, variant id)."""
    audit = {"mutants_per_task": 4, "refactorings_per_task": 2, **section}
    data = {"name": "a", "benchmark": "audit", "suite": str(SUITE_DIR), "tasks": {"ids": [TASK]}, "audit": audit}
    jobs = plan_run(sweep_config_from(data | {"output": str(tmp_path)}, tmp_path), notice=lambda _: None).jobs
    return {(job.body.variant, job.body.variant_id): job for job in jobs}  # type: ignore[attr-defined]


def test_only_mutants_stop_and_only_their_ids_say_so(tmp_path: Path) -> None:
    stopping, full = planned(tmp_path), planned(tmp_path, stop_at_first_kill=False)
    assert stopping.keys() == full.keys() and {kind for kind, _ in stopping} == {"golden", "mutant", "refactoring"}
    for key, job in stopping.items():
        mutant = key[0] == "mutant"
        assert job.body.stop_at_first_failure is mutant and full[key].body.stop_at_first_failure is False  # type: ignore[attr-defined]
        # A mutant judged to its first failure is another job than one judged by every test; the rest are the same.
        assert (job.job_id != full[key].job_id) is mutant
        sent = worker_job(job, 1, 60)
        assert isinstance(sent, AuditSpec) and sent.stop_at_first_failure is mutant


def test_the_evaluation_spec_names_the_stop_only_when_asked() -> None:
    """Left out of the dump unless set: specs, task hashes and job ids made before the option stay as they were."""
    spec = EvaluationSpec(script_name="e.js", script_source="module.exports = () => ({});", timeout_s=5)
    assert "stop_at_first_failure" not in spec.model_dump()
    stopping = spec.model_copy(update={"stop_at_first_failure": True})
    assert stopping.model_dump()["stop_at_first_failure"] is True
    assert EvaluationSpec.model_validate(stopping.model_dump()) == stopping


def test_a_killed_mutants_row_names_the_test_that_killed_it(tmp_path: Path) -> None:
    job = next(job for (kind, _), job in planned(tmp_path).items() if kind == "mutant")
    tests = [TestVerdict(name="walks right", passed=True), TestVerdict(name="walks up", passed=False)]
    evaluation = EvalResult(
        success=False, passed=1, total=4, psr=0.25, tests=tests, stopped_early=EarlyStop(test="walks up", not_run=2)
    )
    result = JobResult(job_id=job.job_id, attempt=1, outcome="failed", stop_reason="evaluated", evaluation=evaluation)
    row = audit_row(job, result)
    assert (row.verdict, row.stopped_at, row.tests_not_run) == ("killed", "walks up", 2)
    assert (row.tests_passed, row.tests_total, json.loads(row.failing_tests)) == (1, 2, ["walks up"])
    panel = variant_panel({"audits": [row.model_copy(update={"stopped_at": "walks <up>"})]}, tmp_path)
    assert panel is not None and "its tests stopped at walks &lt;up&gt;: 2 after it not run" in panel.html
    ran_all = evaluation.model_copy(update={"stopped_early": None, "total": 2, "psr": 0.5})
    row = audit_row(job, result.model_copy(update={"evaluation": ran_all}))
    assert (row.verdict, row.stopped_at, row.tests_not_run) == ("killed", None, None)


def manifest_of(tmp_path: Path, stored_audit: dict[str, Any]) -> Path:
    """A run directory whose manifest stores ``stored_audit`` as its config's audit section."""
    data = {"name": "a", "benchmark": "audit", "suite": str(SUITE_DIR), "tasks": {"ids": [TASK]}, "output": "x"}
    plan = plan_run(sweep_config_from(data | {"audit": {"mutants_per_task": 4}}, tmp_path), notice=lambda _: None)
    config = plan.config.model_dump(mode="json") | {"audit": stored_audit}
    manifest = RunManifest(
        run_name="a", schema_version=SCHEMA_VERSION, harness=plan.harness, config=config,
        config_hash=f"hash {sorted(stored_audit.items())}", suite=plan.suite, planned_jobs=len(plan.jobs),
    )  # fmt: skip
    run_dir = tmp_path / "run"
    run_dir.mkdir(exist_ok=True)
    write_manifest(run_dir, manifest)
    return run_dir


def test_a_variant_page_finds_mutants_planned_before_they_could_stop(tmp_path: Path) -> None:
    """A run stored before the option planned its mutants to run every test: their pages still make them again."""
    mutant = next(job for (kind, _), job in planned(tmp_path, stop_at_first_kill=False).items() if kind == "mutant")
    old = manifest_of(tmp_path, {"mutants_per_task": 4, "refactorings_per_task": 2, "seed": 0})
    assert remade_programs(old, TASK, mutant.job_id).variant is not None
    stopping = next(job for (kind, _), job in planned(tmp_path).items() if kind == "mutant")
    new = manifest_of(
        tmp_path, {"mutants_per_task": 4, "refactorings_per_task": 2, "seed": 0, "stop_at_first_kill": True}
    )
    assert remade_programs(new, TASK, stopping.job_id).variant is not None
    with pytest.raises(ProgramsUnavailableError):
        remade_programs(new, TASK, mutant.job_id)
