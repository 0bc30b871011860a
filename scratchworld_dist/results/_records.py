"""Result rows: one per finished job, one per step, one per unit test, and the rows of the job kind's own tables.

The row models are the only shape results take, in the journal, in Parquet and in reports;
``_schema.py`` derives the Arrow schemas from the same field lists.
"""

from __future__ import annotations

import json
from datetime import UTC, datetime
from typing import Any

from pydantic import BaseModel, ConfigDict, Field, SerializeAsAny, model_validator

from scratchworld_dist.kinds import job_kind
from scratchworld_dist.suites import StabilityMarks
from scratchworld_dist.sweep import JobSpec
from workers.contract import MIB, EvalResult, JobResult


class JobRow(BaseModel):
    """One finished attempt of one job (a row of ``jobs/``)."""

    model_config = ConfigDict(frozen=True)

    run_name: str
    job_id: str
    attempt: int
    model: str
    litellm_model: str | None
    mode: str
    agent: str
    task_id: str
    category: str
    task_hash: str
    suite_hash: str
    seed: int
    max_steps: int
    harness_fingerprint: str | None
    """Digest of the code and editor that ran the job (see ``workers.harness_fingerprint``); null in older runs."""

    outcome: str
    """``passed`` (all tests), ``failed`` (evaluated, not all pass) or ``error`` (no verdict)."""

    error_class: str | None
    error_message: str | None
    eval_error_kind: str | None
    """The evaluation's own error kind when a project failed by breaking the script (e.g. script_error)."""

    eval_profile: str | None
    """Evaluation profile the verdict was made under (native | upstream); null if none was reached."""

    eval_clock: str | None = None
    """Clock the verdict was made on (virtual | real); null if none was reached (and in older journals)."""

    eval_render: str | None = None
    """When the evaluation drew the stage (on_demand | every_frame); null if no verdict was reached (and in
    older runs, whose evaluations drew every frame)."""

    eval_page: str | None = None
    """The page the evaluation ran in (bare | editor); null if no verdict was reached (and in older runs,
    whose evaluations ran in the editor)."""

    eval_timing: str | None = None
    """How the VM's frames were timed (ideal | calibrated under the virtual clock, real on the real clock);
    null if no verdict was reached (and in older runs, whose virtual frames were ideal)."""

    stop_reason: str
    tests_passed: int
    tests_total: int
    psr: float | None
    """Fraction of tests passed; null for ``error`` rows, which have no verdict."""

    steps: int
    llm_calls: int
    input_tokens: int
    output_tokens: int
    cost_usd: float
    episode_s: float
    setup_s: float
    agent_s: float
    evaluation_s: float
    started_at: datetime
    finished_at: datetime
    worker_node: str | None
    worker_host: str | None
    worker_pid: int | None
    worker_index: int | None
    artifact_dir: str | None
    """Folder of this attempt's final.sb3 and trajectory.jsonl, relative to the run directory."""

    memory_wave: int | None = None
    """A learning agent's wave in its memory stream (null without memory, and in older runs)."""

    memory_snapshot: str | None = None
    """Digest of the memory snapshot the job was shown (see ``memory/<store>/wave-*.json``)."""

    llm_cache_hits: int | None = None
    """Of ``llm_calls``, those answered from the model cache; null when the run had no cache (and in older runs)."""

    editors_held: int | None = None
    """Editor pages the worker's browser held when the episode ended (null if no worker answered; older runs)."""

    browser_pss_mb: float | None = None
    """Proportional set size of the worker's browser then, in MiB (``/ editors_held``: memory per editor)."""

    node_available_mb: float | None = None
    """The node's available memory then, in MiB."""

    setting: str | None = None
    """A drag job's setting (baseline | gt_start | knowledge); null for episodes (and in older runs)."""

    regraded_from: str | None = None
    """A regrade's source job id (its agent-side columns are that job's); null otherwise (and in older runs)."""

    benchmark: str | None = None
    """The job's kind (``tasks``, ``drag``, ``perception`` or a plugin's), as the sweep config's ``benchmark:``.
    Null only in shards written before schema 4: ``RunStore.job_rows`` fills in the run's kind."""


class StepRow(BaseModel):
    """One agent action of one attempt (a row of ``steps/``)."""

    model_config = ConfigDict(frozen=True)

    job_id: str
    attempt: int
    step: int
    action: str
    args_json: str
    ok: bool
    error_code: str | None
    error_message: str | None
    latency_s: float
    observation_s: float
    warnings: str | None
    """The step's observation warnings, one per line (None when there were none)."""

    llm_calls: int
    input_tokens: int
    output_tokens: int
    cost_usd: float
    llm_cache_hits: int | None = None
    """Of ``llm_calls``, those answered from the model cache; null when the run had no cache (and in older runs)."""


class TestRow(BaseModel):
    """One unit test of one evaluated attempt (a row of ``tests/``)."""

    __test__ = False
    model_config = ConfigDict(frozen=True)

    job_id: str
    attempt: int
    task_id: str
    test_index: int
    name: str
    passed: bool
    error: str | None
    duration_ms: float | None
    unstable: bool | None = None
    """Whether the suite's known test stability named this test unstable when the run was planned (see
    ``SuiteInfo.stability``); null when it did not cover the task (and in older runs)."""


class JobRecord(BaseModel):
    """Everything one attempt adds to the results, committed together."""

    job: JobRow
    steps: list[StepRow] = Field(default_factory=list)
    tests: list[TestRow] = Field(default_factory=list)
    kind_rows: dict[str, list[SerializeAsAny[BaseModel]]] = Field(default_factory=dict)
    """Rows of the job kind's own tables (``JobKind.tables``: ``drags``, ``perception``...), by table."""

    @model_validator(mode="before")
    @classmethod
    def _typed_kind_rows(cls, data: Any) -> Any:
        """Each kind table's rows as its row model; a table given as a field of its own (``drags=[...]``, and
        journal lines written before ``kind_rows``) is one of them."""
        from scratchworld_dist.results._schema import table_model  # derived from these rows: imported after them

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
    kind = job_kind(job.benchmark)
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


def shared_image_path(sha256: str) -> str:
    """Where a run keeps an image its jobs share (a perception item's screenshot), relative to the run directory."""
    return f"images/{sha256}.png"
