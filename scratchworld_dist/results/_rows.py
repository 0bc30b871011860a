"""Result rows every run has: one per finished job, one per step, one per unit test.

The row models are the only shape results take, in the journal, in Parquet and in reports;
``_schema.py`` derives the Arrow schemas from the same field lists (a kind's own tables add theirs).
"""

from __future__ import annotations

from datetime import datetime

from pydantic import BaseModel, ConfigDict


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

    eval_seed: int | None = None
    """The seed the evaluation drew ``Math.random`` from (``workers.contract.evaluation_seed``: the task and
    the sweep seed); null if no verdict was reached (and in older runs, whose evaluations were unseeded)."""

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


def shared_image_path(sha256: str) -> str:
    """Where a run keeps an image its jobs share (a perception item's screenshot), relative to the run directory."""
    return f"images/{sha256}.png"
