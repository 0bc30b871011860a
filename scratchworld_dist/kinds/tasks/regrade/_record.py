"""Committing a regrade's attempt: the source's artifacts linked in, then its rows (the commit point).

The row keeps the source's agent-side columns (model, agent, task, seed, steps, tokens, cost, agent
time, memory) and takes the new identity, verdict, evaluation time and worker; the steps are the
source attempt's, the tests the new evaluation's. The new run directory holds the trajectory, its
images and the project, so a viewer needs nothing of the source.
"""

from __future__ import annotations

from datetime import UTC, datetime

from scratchworld_dist.kinds.tasks.regrade._plan import RegradeJob
from scratchworld_dist.results import JobRecord, JobRow, RunStore, StepRow, test_rows
from scratchworld_dist.sweep import SuiteInfo
from workers.contract import MIB, JobResult


class RegradeRecorder:
    """Commits every finished regrade attempt to ``store``."""

    def __init__(self, store: RunStore, run_name: str, suite: SuiteInfo, steps: dict[str, list[StepRow]]) -> None:
        self.store = store
        self.run_name = run_name
        self.suite = suite
        self.steps = steps

    def __call__(self, job: RegradeJob, result: JobResult) -> None:
        artifact_dir = None
        folder = job.source.artifacts
        for path in sorted(folder.rglob("*")):
            if path.is_file() and not path.name.startswith("."):
                name = path.relative_to(folder).as_posix()
                artifact_dir = self.store.link_artifact(job.job_id, result.attempt, name, path)
        source = job.source.row
        steps = [
            s.model_copy(update={"job_id": job.job_id, "attempt": result.attempt})
            for s in self.steps.get(source.job_id, [])
        ]
        record = JobRecord(
            job=regraded_row(job, result, self.run_name, self.suite.hash, artifact_dir),
            steps=steps,
            tests=test_rows(job.job_id, result.attempt, job.task_id, result.evaluation, self.suite.stability),
        )
        self.store.commit(record)


def regraded_row(
    job: RegradeJob, result: JobResult, run_name: str, suite_hash: str, artifact_dir: str | None
) -> JobRow:
    """The source's row with the regrade's identity, verdict, timing and worker."""
    source, evaluation = job.source.row, result.evaluation
    conditions = evaluation.conditions if evaluation is not None else None
    worker, load = result.worker, result.load
    return JobRow.model_validate(
        {
            **source.model_dump(),
            "run_name": run_name,
            "job_id": job.job_id,
            "attempt": result.attempt,
            "task_hash": job.task_hash,
            "suite_hash": suite_hash,
            "harness_fingerprint": job.harness,
            "outcome": result.outcome,
            "error_class": result.error_class,
            "error_message": result.error_message,
            "eval_error_kind": evaluation.error.kind if evaluation is not None and evaluation.error else None,
            "eval_profile": conditions.profile if conditions else None,
            "eval_clock": conditions.clock if conditions else None,
            "eval_render": conditions.render if conditions else None,
            "eval_page": conditions.page if conditions else None,
            "eval_timing": conditions.timing if conditions else None,
            "eval_seed": evaluation.random_seed if evaluation is not None else None,
            # The agent stopped as it did; a regrade without a verdict says why it has none.
            "stop_reason": result.stop_reason if result.outcome == "error" else source.stop_reason,
            "tests_passed": evaluation.passed if evaluation is not None else 0,
            "tests_total": evaluation.total if evaluation is not None else 0,
            "psr": None if result.outcome == "error" or evaluation is None else evaluation.psr,
            "episode_s": result.timings.total_s,
            "evaluation_s": result.timings.evaluation_s,
            "started_at": datetime.fromtimestamp(result.started_at, tz=UTC),
            "finished_at": datetime.fromtimestamp(result.finished_at, tz=UTC),
            "worker_node": worker.node_id if worker else None,
            "worker_host": worker.hostname if worker else None,
            "worker_pid": worker.pid if worker else None,
            "worker_index": worker.worker_index if worker else None,
            "artifact_dir": artifact_dir,
            "editors_held": load.editors if load else None,
            "browser_pss_mb": load.browser_pss_bytes / MIB if load else None,
            "node_available_mb": load.node_available_bytes / MIB if load else None,
            "regraded_from": source.job_id,
        }
    )
