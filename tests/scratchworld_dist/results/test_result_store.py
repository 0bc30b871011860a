"""The run directory's store: journal, atomic Parquet shards, crash recovery, locking and the views on top."""

from __future__ import annotations

import json
import random
import shutil
import subprocess
import sys
from collections.abc import Iterator
from datetime import UTC, datetime
from pathlib import Path

import duckdb
import pandas as pd
import polars as pl
import pyarrow.dataset as ds
import pyarrow.parquet as pq
import pytest

from scratchworld_dist._errors import RunDirError
from scratchworld_dist.kinds.tasks import EpisodeBody
from scratchworld_dist.results import (
    CORE_TABLES,
    SCHEMA_VERSION,
    JobRecord,
    JobRow,
    RunStore,
    effective_rows,
    record_of,
    row_tables,
    table_schema,
)
from scratchworld_dist.results import _store as store_module
from scratchworld_dist.sweep import JobSpec
from workers.contract import (
    AgentRef,
    EpisodeTimings,
    EvalResult,
    JobResult,
    ModelSpec,
    StepRecord,
    TestVerdict,
    WorkerInfo,
)

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


@pytest.fixture
def writer(tmp_path: Path) -> Iterator[RunStore]:
    store = RunStore(tmp_path / "run")
    store.open_for_writing()
    yield store
    store.close()


_CRASHING_DRIVER = """
import os, sys
from pathlib import Path
from scratchworld_dist.results import JobRecord, RunStore
store = RunStore(Path(sys.argv[1]))
store.open_for_writing()
for line in sys.stdin.read().splitlines():
    store.commit(JobRecord.model_validate_json(line))
os._exit(0)  # killed: no close(), no compaction, only what commit() made durable
"""


@pytest.fixture(scope="module")
def crashed_template(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A run directory whose driver died after committing three attempts (made once, copied per test)."""
    run_dir = tmp_path_factory.mktemp("crashed") / "run"
    lines = "\n".join(record(n).model_dump_json() for n in range(3))
    subprocess.run([sys.executable, "-c", _CRASHING_DRIVER, str(run_dir)], input=lines, text=True, check=True)
    return run_dir


@pytest.fixture
def crashed(tmp_path: Path, crashed_template: Path) -> Path:
    run_dir = tmp_path / "run"
    shutil.copytree(crashed_template, run_dir)
    return run_dir


# --- rows ----------------------------------------------------------------------------------------


def test_record_of_flattens_a_verdict() -> None:
    rec = record(7, attempt=2, outcome="failed")
    job = rec.job
    assert (job.run_name, job.job_id, job.attempt, job.task_id, job.seed) == ("unit", "job007", 2, "task_7", 1)
    assert (job.model, job.litellm_model, job.mode, job.agent) == ("gpt", "openai/gpt-4o", "composite", "llm")
    assert (job.task_hash, job.suite_hash, job.harness_fingerprint) == (f"{7:016x}", "suitehash", "f1ngerpr1nt00000")
    assert (job.outcome, job.error_class, job.eval_error_kind, job.stop_reason) == ("failed", None, None, "done")
    assert (job.tests_passed, job.tests_total, job.psr) == (1, 2, 0.5)
    assert (job.steps, job.llm_calls, job.input_tokens, job.output_tokens) == (2, 2, 250, 25)
    assert job.cost_usd == pytest.approx(0.03)
    assert (job.episode_s, job.setup_s, job.agent_s, job.evaluation_s) == (3.5, 1.0, 2.0, 0.5)
    assert job.started_at == datetime.fromtimestamp(T0, tz=UTC)
    assert (job.worker_node, job.worker_host, job.worker_pid, job.worker_index) == ("node-a", "host-a", 4242, 1)
    assert job.artifact_dir == "artifacts/job007/attempt-2"
    assert [(s.job_id, s.attempt, s.step, s.action) for s in rec.steps] == [
        ("job007", 2, 0, "load_project"),
        ("job007", 2, 1, "done"),
    ]
    assert rec.steps[0].args_json == '{"a": "x", "z": 1}'
    assert [(t.test_index, t.name, t.passed, t.task_id) for t in rec.tests] == [
        (0, "runs", True, "task_7"),
        (1, "behaves", False, "task_7"),
    ]


def test_record_of_an_error_has_no_verdict() -> None:
    rec = record(1, outcome="error")
    assert (rec.job.outcome, rec.job.error_class, rec.job.error_message) == ("error", "editor_failure", "page crashed")
    assert rec.job.psr is None
    assert (rec.job.tests_passed, rec.job.tests_total, rec.tests) == (0, 0, [])
    assert len(rec.steps) == 2


def test_record_of_keeps_the_evaluation_error_kind() -> None:
    job = spec(2)
    result = JobResult(
        job_id=job.job_id,
        attempt=1,
        outcome="failed",
        stop_reason="done",
        evaluation=EvalResult.failure("script_error", "TypeError in evaluate.js"),
    )
    rec = record_of(job, result, run_name="unit", suite_hash="s", artifact_dir=None)
    assert (rec.job.outcome, rec.job.eval_error_kind, rec.job.psr) == ("failed", "script_error", 0.0)
    assert rec.job.worker_node is None and rec.job.artifact_dir is None


def test_scripted_agent_rows_carry_no_model() -> None:
    job = spec(3).model_copy(update={"model": None, "agent": AgentRef(name="oracle")})
    rec = record_of(job, episode(job, 1, "passed"), run_name="u", suite_hash="s", artifact_dir=None)
    assert (rec.job.model, rec.job.litellm_model, rec.job.agent) == ("-", None, "oracle")


# --- writing and reading back ------------------------------------------------------------------


def test_commit_then_read_back(tmp_path: Path) -> None:
    run_dir = tmp_path / "run"
    records = [record(0), record(1, outcome="failed"), record(2, outcome="error")]
    store = RunStore(run_dir)
    store.open_for_writing()
    for rec in records:
        store.commit(rec)
    assert segments(run_dir) == ["segment-000001.jsonl"] and shards(run_dir, "jobs") == []
    journal_rows = store.job_rows()
    store.close()

    assert segments(run_dir) == []
    for table in ("jobs", "steps", "tests"):
        assert shards(run_dir, table) == ["part-000001.parquet"]
    reader = RunStore(run_dir)
    assert reader.job_rows() == [r.job for r in records] == journal_rows
    steps = reader.read_table("steps")
    assert steps.num_rows == 6
    assert steps.column("job_id").to_pylist() == ["job000"] * 2 + ["job001"] * 2 + ["job002"] * 2
    assert steps.column("error_message").to_pylist()[-1] == "ünïcode failure"
    tests = reader.read_table("tests")
    assert tests.num_rows == 4  # the error attempt has no tests
    assert tests.column("passed").to_pylist() == [True, True, True, False]
    outcomes = reader.read_table("jobs", columns=["job_id", "outcome"])
    assert outcomes.column_names == ["job_id", "outcome"]
    assert outcomes.to_pylist()[2] == {"job_id": "job002", "outcome": "error"}
    assert reader.read_table("jobs").column("psr").to_pylist() == [1.0, 0.5, None]


def test_shards_are_readable_by_common_tools(tmp_path: Path) -> None:
    run_dir = tmp_path / "run"
    store = RunStore(run_dir)
    store.open_for_writing()
    for n in range(4):
        store.commit(record(n, outcome="passed" if n % 2 else "failed"))
    store.close()

    dataset = ds.dataset(run_dir / "jobs", format="parquet")
    assert dataset.to_table().num_rows == 4
    assert sorted(dataset.to_table(columns=["job_id"]).column("job_id").to_pylist()) == [
        f"job{n:03d}" for n in range(4)
    ]

    by_outcome = duckdb.sql(
        f"SELECT outcome, count(*) FROM read_parquet('{run_dir}/jobs/*.parquet') GROUP BY outcome ORDER BY outcome"
    ).fetchall()
    assert by_outcome == [("failed", 2), ("passed", 2)]
    assert duckdb.sql(f"SELECT count(*) FROM read_parquet('{run_dir}/steps/*.parquet')").fetchall() == [(8,)]

    frame = pl.read_parquet(f"{run_dir}/tests/*.parquet")
    assert frame.height == 8
    assert frame.filter(pl.col("passed")).height == 6

    jobs = pd.read_parquet(run_dir / "jobs")
    assert len(jobs) == 4
    assert jobs["psr"].tolist() == [0.5, 1.0, 0.5, 1.0]
    assert str(jobs["started_at"].dt.tz) == "UTC"
    assert jobs["started_at"].iloc[0].timestamp() == T0


def test_shards_carry_schema_and_version(writer: RunStore) -> None:
    writer.commit(record(0))
    writer.flush()
    for table in CORE_TABLES:  # a task episode's run holds no other kind's tables
        schema = table_schema(table)
        written = pq.read_schema(writer.table_dir(table) / "part-000001.parquet")
        assert written.metadata[b"scratchworld_schema_version"] == str(SCHEMA_VERSION).encode()
        assert written.remove_metadata().equals(schema.remove_metadata()), table
    jobs = pq.read_schema(writer.table_dir("jobs") / "part-000001.parquet")
    assert not jobs.field("job_id").nullable and jobs.field("psr").nullable
    assert str(jobs.field("started_at").type) == "timestamp[us, tz=UTC]"


def test_uncompacted_commits_are_visible_to_another_reader(writer: RunStore) -> None:
    writer.commit(record(0))
    writer.commit(record(1))
    reader = RunStore(writer.run_dir)
    assert [r.job_id for r in reader.job_rows()] == ["job000", "job001"]
    assert reader.read_table("steps").num_rows == 4
    assert shards(writer.run_dir, "jobs") == []

    writer.flush()  # now one shard, then more journal on top of it
    writer.commit(record(2))
    assert shards(writer.run_dir, "jobs") == ["part-000001.parquet"]
    assert segments(writer.run_dir) == ["segment-000002.jsonl"]
    assert [r.job_id for r in reader.job_rows()] == ["job000", "job001", "job002"]
    assert reader.read_table("tests", columns=["job_id"]).num_rows == 6


def test_segments_roll_over(writer: RunStore, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(store_module, "SEGMENT_ROWS", 2)
    for n in range(5):
        writer.commit(record(n))
    assert shards(writer.run_dir, "jobs") == ["part-000001.parquet", "part-000002.parquet"]
    assert segments(writer.run_dir) == ["segment-000003.jsonl"]
    assert len(RunStore(writer.run_dir).job_rows()) == 5


def test_empty_or_missing_run_dir_reads_as_empty_tables(tmp_path: Path) -> None:
    reader = RunStore(tmp_path / "nothing")
    for table in row_tables():
        schema = table_schema(table)
        empty = reader.read_table(table)
        assert empty.num_rows == 0 and empty.schema.equals(schema)
    assert reader.read_table("jobs", columns=["job_id"]).column_names == ["job_id"]
    assert reader.attempts() == {}


def test_commit_needs_the_lock(tmp_path: Path) -> None:
    with pytest.raises(RuntimeError, match="open_for_writing"):
        RunStore(tmp_path / "run").commit(record(0))


def test_write_artifact(writer: RunStore) -> None:
    folder = writer.write_artifact("job001", 2, "final.sb3", b"PK\x03\x04")
    assert folder == "artifacts/job001/attempt-2"
    assert (writer.run_dir / folder / "final.sb3").read_bytes() == b"PK\x03\x04"


# --- crashes and recovery ----------------------------------------------------------------------


def test_crashed_driver_leaves_its_commits_in_the_journal(crashed: Path) -> None:
    assert segments(crashed) == ["segment-000001.jsonl"]
    assert shards(crashed, "jobs") == []
    assert [r.job_id for r in RunStore(crashed).job_rows()] == ["job000", "job001", "job002"]


def test_leftover_segment_is_compacted_by_the_next_writer(crashed: Path) -> None:
    store = RunStore(crashed)
    store.open_for_writing()
    assert segments(crashed) == []
    assert shards(crashed, "jobs") == shards(crashed, "steps") == ["part-000001.parquet"]
    store.commit(record(3))
    assert segments(crashed) == ["segment-000002.jsonl"]  # a new segment, never the compacted one's number
    store.close()
    assert shards(crashed, "jobs") == ["part-000001.parquet", "part-000002.parquet"]
    assert [r.job_id for r in RunStore(crashed).job_rows()] == ["job000", "job001", "job002", "job003"]
    assert RunStore(crashed).read_table("steps").num_rows == 8


def _tear(segment: Path, rec: JobRecord) -> None:
    """What a driver killed in the middle of ``write`` leaves: half a line, no newline."""
    line = rec.model_dump_json().encode()
    with segment.open("ab") as handle:
        handle.write(line[: len(line) // 2])


def test_torn_last_line_is_dropped_on_read_and_recovery(crashed: Path) -> None:
    _tear(crashed / "journal" / "segment-000001.jsonl", record(9))
    assert [r.job_id for r in RunStore(crashed).job_rows()] == ["job000", "job001", "job002"]

    store = RunStore(crashed)
    store.open_for_writing()
    store.close()
    assert segments(crashed) == []
    assert [r.job_id for r in RunStore(crashed).job_rows()] == ["job000", "job001", "job002"]


def test_torn_multibyte_character_is_dropped(crashed: Path) -> None:
    segment = crashed / "journal" / "segment-000001.jsonl"
    line = record(9, outcome="error").model_dump_json().encode()
    cut = line.index("ü".encode()) + 1  # inside the two-byte character
    with segment.open("ab") as handle:
        handle.write(line[:cut])
    assert len(RunStore(crashed).job_rows()) == 3


def test_corrupt_middle_line_is_an_error(crashed: Path) -> None:
    segment = crashed / "journal" / "segment-000001.jsonl"
    lines = segment.read_bytes().splitlines(keepends=True)
    lines[1] = lines[1][:40] + b"\n"
    segment.write_bytes(b"".join(lines))
    with pytest.raises(RunDirError, match=r"segment-000001\.jsonl:2: corrupt journal line"):
        RunStore(crashed).read_table("jobs")
    store = RunStore(crashed)
    with pytest.raises(RunDirError, match="corrupt journal line"):
        store.open_for_writing()
    store.close()
    assert segments(crashed) == ["segment-000001.jsonl"]  # nothing was thrown away


def test_compaction_is_idempotent(tmp_path: Path) -> None:
    run_dir = tmp_path / "run"
    store = RunStore(run_dir)
    store.open_for_writing()
    for n in range(3):
        store.commit(record(n))
    segment = run_dir / "journal" / "segment-000001.jsonl"
    aside = tmp_path / "segment.copy"
    shutil.copy(segment, aside)
    store.close()
    # The driver died after writing the jobs shard but before deleting the segment.
    shutil.copy(aside, segment)

    reader = RunStore(run_dir)
    assert len(reader.job_rows()) == 3, "a segment whose jobs shard exists is already counted"
    assert reader.read_table("steps").num_rows == 6
    assert reader.read_table("tests").num_rows == 6

    again = RunStore(run_dir)
    again.open_for_writing()
    assert segments(run_dir) == []
    again.commit(record(3))
    again.close()
    assert shards(run_dir, "jobs") == ["part-000001.parquet", "part-000002.parquet"]
    rows = RunStore(run_dir).job_rows()
    assert sorted(r.job_id for r in rows) == ["job000", "job001", "job002", "job003"]
    assert RunStore(run_dir).read_table("steps").num_rows == 8
    assert duckdb.sql(f"SELECT count(*) FROM read_parquet('{run_dir}/jobs/*.parquet')").fetchall() == [(4,)]


def test_crash_between_shards_counts_the_segment_once(tmp_path: Path) -> None:
    """Steps and tests shards are written before the jobs shard; until that one exists, the journal counts."""
    run_dir = tmp_path / "run"
    store = RunStore(run_dir)
    store.open_for_writing()
    store.commit(record(0))
    store.commit(record(1))
    segment = run_dir / "journal" / "segment-000001.jsonl"
    aside = tmp_path / "segment.copy"
    shutil.copy(segment, aside)
    store.close()
    shutil.copy(aside, segment)
    (run_dir / "jobs" / "part-000001.parquet").unlink()  # died after steps and tests, before jobs

    reader = RunStore(run_dir)
    assert len(reader.job_rows()) == 2
    assert reader.read_table("steps").num_rows == 4
    assert reader.read_table("tests").num_rows == 4


def test_reader_racing_a_compaction_sees_every_row_once(writer: RunStore, monkeypatch: pytest.MonkeyPatch) -> None:
    """The writer compacts (and deletes) a segment after a reader listed it but before it read it."""
    for n in range(3):
        writer.commit(record(n))
    read_segment = store_module._read_segment
    raced: list[Path] = []

    def compact_first(path: Path) -> list[JobRecord]:
        if not raced:
            raced.append(path)
            writer.flush()
        return read_segment(path)

    monkeypatch.setattr(store_module, "_read_segment", compact_first)
    rows = RunStore(writer.run_dir).job_rows()
    assert raced and not raced[0].exists()
    assert [r.job_id for r in rows] == ["job000", "job001", "job002"]


# --- the writer's lock -------------------------------------------------------------------------


def test_second_writer_is_refused_while_the_first_holds_the_lock(writer: RunStore) -> None:
    writer.commit(record(0))
    second = RunStore(writer.run_dir)
    with pytest.raises(RunDirError, match="another scratchworld run is writing here"):
        second.open_for_writing()
    assert segments(writer.run_dir) == ["segment-000001.jsonl"]  # the refused writer compacted nothing
    assert len(second.job_rows()) == 1  # reading needs no lock
    writer.close()
    second.open_for_writing()
    second.close()
    assert len(RunStore(writer.run_dir).job_rows()) == 1


# --- attempts and the effective view -----------------------------------------------------------


def test_attempts_report_the_last_attempt_and_whether_decided(writer: RunStore) -> None:
    writer.commit(record(1, attempt=1, outcome="error"))
    writer.commit(record(2, attempt=1, outcome="error"))
    writer.commit(record(3, attempt=1, outcome="failed"))
    writer.flush()
    writer.commit(record(1, attempt=2, outcome="passed"))
    writer.commit(record(2, attempt=2, outcome="error"))
    assert RunStore(writer.run_dir).attempts() == {"job001": (2, True), "job002": (2, False), "job003": (1, True)}


def test_attempts_keep_a_verdict_when_a_later_attempt_errs(writer: RunStore) -> None:
    writer.commit(record(1, attempt=2, outcome="failed"))
    writer.commit(record(1, attempt=1, outcome="error"))  # delivered out of order
    writer.commit(record(1, attempt=3, outcome="error"))
    assert writer.attempts() == {"job001": (3, True)}


def _row(n: int, attempt: int, outcome: str) -> JobRow:
    return record(n, attempt=attempt, outcome=outcome).job


def test_effective_rows_prefer_a_verdict_then_the_latest_attempt() -> None:
    rows = [
        _row(1, 1, "error"),
        _row(1, 2, "passed"),
        _row(1, 3, "error"),  # a late error does not hide the verdict
        _row(2, 1, "failed"),
        _row(2, 2, "passed"),  # the latest verdict wins
        _row(3, 1, "error"),
        _row(3, 2, "error"),  # only errors: the latest error
        _row(4, 1, "failed"),
    ]
    expected = {"job001": (2, "passed"), "job002": (2, "passed"), "job003": (2, "error"), "job004": (1, "failed")}
    for seed in range(5):
        shuffled = rows[:]
        random.Random(seed).shuffle(shuffled)
        chosen = list(effective_rows(shuffled))
        assert len(chosen) == 4
        assert {r.job_id: (r.attempt, r.outcome) for r in chosen} == expected


def test_effective_rows_of_the_store(writer: RunStore) -> None:
    writer.commit(record(5, attempt=1, outcome="error"))
    writer.commit(record(5, attempt=2, outcome="failed"))
    (row,) = effective_rows(RunStore(writer.run_dir).job_rows())
    assert (row.job_id, row.attempt, row.outcome, row.psr) == ("job005", 2, "failed", 0.5)


def test_journal_lines_are_plain_json(writer: RunStore) -> None:
    writer.commit(record(0))
    (line,) = (writer.run_dir / "journal" / "segment-000001.jsonl").read_text(encoding="utf-8").splitlines()
    assert json.loads(line)["job"]["job_id"] == "job000"
