"""Job records as a worker's results make them (two steps, two tests unless the attempt erred), and what
a run directory holds after commits: its journal segments and its Parquet shards."""

from __future__ import annotations

from pathlib import Path

from scratchworld_dist.kinds.tasks import EpisodeBody
from scratchworld_dist.results import JobRecord, record_of
from scratchworld_dist.sweep import JobSpec
from workers.contract import EpisodeTimings, EvalResult, JobResult, ModelSpec, StepRecord, TestVerdict, WorkerInfo

MODEL = ModelSpec(name="gpt", model="openai/gpt-4o", temperature=0.0, api_key_env="OPENAI_API_KEY")
T0 = 1_790_000_000.25  # a unix time with a fraction, to check sub-second precision survives Parquet


def spec(n: int) -> JobSpec:
    return JobSpec(
        job_id=f"job{n:03d}",
        model=MODEL,
        agent="llm",
        task_id=f"task_{n}",
        category="create",
        task_hash=f"{n:016x}",
        seed=n % 3,
        harness="f1ngerpr1nt00000",
        body=EpisodeBody(mode="composite", max_steps=10),
    )


def episode(job: JobSpec, attempt: int, outcome: str) -> JobResult:
    """A worker's result: two steps, and two tests unless the attempt ended in an error."""
    errored = outcome == "error"
    load = StepRecord(
        index=0,
        action="load_project",
        args={"z": 1, "a": "x"},
        ok=True,
        latency_s=0.5,
        llm_calls=1,
        input_tokens=100,
        output_tokens=20,
        cost_usd=0.01,
    )
    done = StepRecord(
        index=1,
        action="done",
        ok=not errored,
        error_code="E" if errored else None,
        error_message="ünïcode failure" if errored else None,
        latency_s=0.25,
        llm_calls=1,
        input_tokens=150,
        output_tokens=5,
        cost_usd=0.02,
    )
    result = JobResult(
        job_id=job.job_id,
        attempt=attempt,
        outcome="passed",
        stop_reason="done",
        steps=[load, done],
        timings=EpisodeTimings(setup_s=1.0, agent_s=2.0, evaluation_s=0.5, total_s=3.5),
        worker=WorkerInfo(node_id="node-a", hostname="host-a", pid=4242, worker_index=1),
        started_at=T0,
        finished_at=T0 + 3.5,
    )
    if errored:
        update = {"outcome": "error", "error_class": "editor_failure", "error_message": "page crashed"}
        return result.model_copy(update={**update, "stop_reason": "editor_failure"})
    second = TestVerdict(name="behaves", passed=outcome == "passed", duration_ms=4.0)
    tests = [TestVerdict(name="runs", passed=True, duration_ms=3.0), second]
    passed = sum(t.passed for t in tests)
    evaluation = EvalResult(success=passed == 2, passed=passed, total=2, psr=passed / 2, tests=tests)
    return result.model_copy(update={"outcome": outcome, "evaluation": evaluation})


def record(n: int, attempt: int = 1, outcome: str = "passed") -> JobRecord:
    job = spec(n)
    return record_of(
        job,
        episode(job, attempt, outcome),
        run_name="unit",
        suite_hash="suitehash",
        artifact_dir=f"artifacts/{job.job_id}/attempt-{attempt}",
    )


def segments(run_dir: Path) -> list[str]:
    return sorted(p.name for p in (run_dir / "journal").glob("*.jsonl"))


def shards(run_dir: Path, table: str) -> list[str]:
    return sorted(p.name for p in (run_dir / table).glob("*.parquet"))
