"""The run directory's store after a crash: a dead driver's journal, torn and corrupt lines, compaction
that is idempotent and a reader racing it."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import duckdb
import pytest

from scratchworld_dist._errors import RunDirError
from scratchworld_dist.results import JobRecord, RunStore
from scratchworld_dist.results import _store as store_module
from tests.support.records import record, segments, shards

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
