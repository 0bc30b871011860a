"""What one attempt adds to a run's results: its job row, step rows, test rows and the rows of its kind's own
tables, committed together."""

from __future__ import annotations

import json
from datetime import UTC, datetime
from typing import Any

from pydantic import BaseModel, Field, SerializeAsAny, model_validator

from scratchworld_dist.kinds import job_kind
from scratchworld_dist.results._kind import KindRows
from scratchworld_dist.results._rows import JobRow, StepRow, TestRow
from scratchworld_dist.results._schema import table_model
from scratchworld_dist.suites import StabilityMarks
from scratchworld_dist.sweep import JobSpec
from workers.contract import MIB, EvalResult, JobResult


class JobRecord(BaseModel):
    """Everything one attempt adds to the results, committed together."""

    job: JobRow
    steps: list[StepRow] = Field(default_factory=list)
    tests: list[TestRow] = Field(default_factory=list)
    kind_rows: dict[str, list[SerializeAsAny[BaseModel]]] = Field(default_factory=dict)
    """Rows of the job kind's own tables (``KindTraits.tables``: ``drags``, ``perception``...), by table."""

    @model_validator(mode="before")
    @classmethod
    def _typed_kind_rows(cls, data: Any) -> Any:
        """Each kind table's rows as its row model; a table given as a field of its own (``drags=[...]``, and
        journal lines written before ``kind_rows``) is one of them."""
        if not isinstance(data, dict):
            return data
        core = {"job", "steps", "tests"}
        given = {**(data.get("kind_rows") or {}), **{k: v for k, v in data.items() if k not in core | {"kind_rows"}}}
        typed: dict[str, list[BaseModel]] = {}
        for table, rows in given.items():
            model = table_model(table)
            typed[table] = [row if isinstance(row, model) else model.model_validate(row) for row in rows]
        return {**{k: v for k, v in data.items() if k in core}, "kind_rows": typed}


def _time(unix: float) -> datetime:
    return datetime.fromtimestamp(unix, tz=UTC)


def record_of(
    job: JobSpec,
    result: JobResult,
    *,
    run_name: str,
    suite_hash: str,
    artifact_dir: str | None,
    stability: StabilityMarks | None = None,
) -> JobRecord:
    """Flatten a worker's result into rows; the job's identity comes from the plan, not the worker, and the
    rows of its kind's own tables from its kind."""
    evaluation = result.evaluation
    worker, load = result.worker, result.load
    cached = job.model_cache is not None
    row = JobRow(
        run_name=run_name,
        job_id=job.job_id,
        attempt=result.attempt,
        model=job.model_name,
        litellm_model=job.model.model if job.model is not None else None,
        agent=job.agent_label,
        task_id=job.task_id,
        category=job.category,
        task_hash=job.task_hash,
        suite_hash=suite_hash,
        seed=job.seed,
        harness_fingerprint=job.harness,
        outcome=result.outcome,
        error_class=result.error_class,
        error_message=result.error_message,
        eval_error_kind=evaluation.error.kind if evaluation is not None and evaluation.error else None,
        eval_profile=evaluation.conditions.profile if evaluation is not None and evaluation.conditions else None,
        eval_clock=evaluation.conditions.clock if evaluation is not None and evaluation.conditions else None,
        eval_render=evaluation.conditions.render if evaluation is not None and evaluation.conditions else None,
        eval_page=evaluation.conditions.page if evaluation is not None and evaluation.conditions else None,
        eval_timing=evaluation.conditions.timing if evaluation is not None and evaluation.conditions else None,
        eval_seed=evaluation.random_seed if evaluation is not None else None,
        stop_reason=result.stop_reason,
        tests_passed=evaluation.passed if evaluation is not None else 0,
        tests_total=evaluation.total if evaluation is not None else 0,
        psr=None if result.outcome == "error" or evaluation is None else evaluation.psr,
        steps=len(result.steps),
        llm_calls=result.llm_calls,
        input_tokens=result.input_tokens,
        output_tokens=result.output_tokens,
        cost_usd=result.cost_usd,
        episode_s=result.timings.total_s,
        setup_s=result.timings.setup_s,
        agent_s=result.timings.agent_s,
        evaluation_s=result.timings.evaluation_s,
        started_at=_time(result.started_at),
        finished_at=_time(result.finished_at),
        worker_node=worker.node_id if worker else None,
        worker_host=worker.hostname if worker else None,
        worker_pid=worker.pid if worker else None,
        worker_index=worker.worker_index if worker else None,
        artifact_dir=artifact_dir,
        memory_wave=job.memory.wave if job.memory is not None else None,
        memory_snapshot=job.memory_snapshot.digest if job.memory_snapshot is not None else None,
        llm_cache_hits=result.llm_cache_hits if cached else None,
        editors_held=load.editors if load else None,
        browser_pss_mb=load.browser_pss_bytes / MIB if load else None,
        node_available_mb=load.node_available_bytes / MIB if load else None,
        benchmark=job.benchmark,
        **job.body.columns(),
    )
    steps = [
        StepRow(
            job_id=job.job_id,
            attempt=result.attempt,
            step=step.index,
            action=step.action,
            args_json=json.dumps(step.args, sort_keys=True),
            ok=step.ok,
            error_code=step.error_code,
            error_message=step.error_message,
            latency_s=step.latency_s,
            observation_s=step.observation_s,
            warnings="\n".join(step.warnings) or None,
            llm_calls=step.llm_calls,
            input_tokens=step.input_tokens,
            output_tokens=step.output_tokens,
            cost_usd=step.cost_usd,
            llm_cache_hits=step.llm_cache_hits if cached else None,
        )
        for step in result.steps
    ]
    tests = test_rows(job.job_id, result.attempt, job.task_id, evaluation, stability)
    kind = job_kind(job.benchmark, KindRows)
    kind_rows = {table: [] for table in kind.tables} | kind.own_rows(job, result, artifact_dir)
    return JobRecord(job=row, steps=steps, tests=tests, kind_rows=kind_rows)


def test_rows(
    job_id: str,
    attempt: int,
    task_id: str,
    evaluation: EvalResult | None,
    stability: StabilityMarks | None,
) -> list[TestRow]:
    """One row per unit test of an attempt's verdict (none without one), marked from the run's ``stability``."""
    return [
        TestRow(
            job_id=job_id,
            attempt=attempt,
            task_id=task_id,
            test_index=index,
            name=test.name,
            passed=test.passed,
            error=test.error,
            duration_ms=test.duration_ms,
            unstable=stability.is_unstable(task_id, test.name) if stability is not None else None,
        )
        for index, test in enumerate(evaluation.tests if evaluation is not None else [])
    ]
