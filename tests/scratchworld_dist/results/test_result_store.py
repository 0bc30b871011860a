"""The run directory's store: rows, atomic Parquet shards read back by common tools, the writer's lock,
and the views on top (attempts, effective rows); its crash recovery is in test_result_recovery.py."""

from __future__ import annotations

import json
import random
from datetime import UTC, datetime
from pathlib import Path

import duckdb
import pandas as pd
import polars as pl
import pyarrow.dataset as ds
import pyarrow.parquet as pq
import pytest

from scratchworld_dist._errors import RunDirError
from scratchworld_dist.results import (
    CORE_TABLES,
    SCHEMA_VERSION,
    JobRow,
    RunStore,
    effective_rows,
    record_of,
    row_tables,
    table_schema,
)
from scratchworld_dist.results import _store as store_module
from tests.support.records import T0, episode, record, segments, shards, spec
from workers.contract import AgentRef, EvalResult, JobResult

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
