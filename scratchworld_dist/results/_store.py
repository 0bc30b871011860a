"""A run directory's results: a write-ahead journal, compacted into atomic Parquet shards.

Each finished attempt is appended as one JSON line to the current journal segment and flushed
before the driver moves on, so killing the driver loses only jobs still in flight. A segment is
compacted into ``jobs/``, ``steps/``, ``tests/``, ``drags/`` and ``perception/`` shards named after it
(temp file + rename, ``jobs`` last), then deleted; compaction is idempotent, so a crash half-way is repaired by
compacting the leftover segment again on the next open. Readers see shards plus any journal.

Layout::

    RUN_DIR/manifest.json
    RUN_DIR/jobs/part-000001.parquet   steps/...   tests/...   drags/...   perception/part-000001.parquet
    RUN_DIR/journal/segment-000002.jsonl   (not yet compacted)
    RUN_DIR/artifacts/<job_id>/attempt-<n>/{final.sb3, trajectory.jsonl, video.mp4, video.json}
    RUN_DIR/images/<sha256>.png   (images many jobs share, e.g. perception screenshots: once per run)

A writer may have a listener (``StoreListener``: a remote run directory's uploader) told of each commit,
compaction and stored file. A store on a view of a remote run (``remote._view``) reads the shards in the bucket.
"""

from __future__ import annotations

import fcntl
import re
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import IO, TYPE_CHECKING, Any, Protocol, TypeVar

import pyarrow as pa
import pyarrow.dataset as ds
import pyarrow.parquet as pq
from pydantic import ValidationError

from scratchworld_dist._errors import RunDirError, validation_summary
from scratchworld_dist._files import link_atomic, write_atomic
from scratchworld_dist.kinds import DEFAULT_KIND, UnknownKindError, job_kind, job_kinds
from scratchworld_dist.results._kind import KindRows
from scratchworld_dist.results._records import JobRecord
from scratchworld_dist.results._rows import JobRow
from scratchworld_dist.results._schema import CORE_TABLES, KIND_TABLE_KEYS, table_schema
from scratchworld_dist.results.remote._view import view_of

if TYPE_CHECKING:
    from scratchworld_dist.results.remote._view import RemoteView


class _Named(Protocol):
    @property
    def job_id(self) -> str: ...


_Job = TypeVar("_Job", bound=_Named)

VIDEO_FILE = "video.mp4"
"""An attempt's episode video (``record.video``), among its artifacts."""

VIDEO_INFO_FILE = "video.json"
"""Beside it: its ``VideoInfo`` (when it starts on the wall clock, to line it up with the steps)."""


class StoreListener(Protocol):
    """Told what a writing store has made durable (``remote.RemoteRun`` copies it to a bucket)."""

    def committed(self, segment: int, line: int, data: bytes) -> None: ...

    def compacted(self, segment: int, tables: list[str]) -> None: ...

    def stored(self, relative: str) -> None: ...


SEGMENT_ROWS = 200
"""Attempts per journal segment before it is compacted into shards."""

_SEGMENT = re.compile(r"^segment-(\d{6})\.jsonl$")
_PART = re.compile(r"^part-(\d{6})\.parquet$")


def unwritable(run_dir: Path, exc: OSError) -> RunDirError:
    """The one-line error for a run directory that cannot take results (where, and the OS's reason)."""
    where = f" ({exc.filename})" if exc.filename and str(exc.filename) != str(run_dir) else ""
    return RunDirError(f"{run_dir}: cannot write results here: {exc.strerror or exc}{where}")


def _read_segment(path: Path) -> list[JobRecord]:
    """Records of a segment; a torn last line (the driver died mid-write) is dropped."""
    records: list[JobRecord] = []
    lines = path.read_bytes().splitlines()
    for number, line in enumerate(lines, start=1):
        if not line.strip():
            continue
        try:
            records.append(JobRecord.model_validate_json(line))
        except ValidationError as exc:
            if number == len(lines):
                break
            raise RunDirError(f"{path}:{number}: corrupt journal line: {validation_summary(exc)}") from exc
    return records


_KEYS: dict[str, tuple[str, ...]] = {
    "jobs": ("job_id", "attempt", "outcome"),
    "steps": ("job_id", "attempt", "step"),
    "tests": ("job_id", "attempt", "test_index"),
}
"""Columns every shard of a table has had in every schema version (a kind's table: ``KIND_TABLE_KEYS``): a file
without them is not one."""


def _check_shard(path: str, table: str, filesystem: Any = None) -> None:
    """Refuse, naming it, a file in a table's folder that is not one of its shards (torn, or foreign)."""
    try:
        schema = pq.read_schema(path, filesystem=filesystem)
    except (OSError, pa.ArrowInvalid) as exc:
        raise RunDirError(f"{path}: unreadable shard ({' '.join(str(exc).split())})") from exc
    missing = [name for name in _KEYS.get(table, KIND_TABLE_KEYS) if name not in schema.names]
    if b"scratchworld_schema_version" not in (schema.metadata or {}) or missing:
        lacks = f"lacks column(s) {', '.join(missing)}" if missing else "has no scratchworld_schema_version"
        raise RunDirError(f"{path}: not a shard of the {table} table ({lacks}); move it out of the run directory")


def _to_table(records: list[JobRecord], table: str) -> pa.Table:
    """One table's rows of some records, with that table's schema."""
    if table == "jobs":
        rows = [r.job.model_dump() for r in records]
    elif table in CORE_TABLES:
        rows = [row.model_dump() for r in records for row in getattr(r, table)]
    else:
        rows = [row.model_dump() for r in records for row in r.kind_rows.get(table, [])]
    return pa.Table.from_pylist(rows, schema=table_schema(table))


def _segment_tables(records: list[JobRecord]) -> list[str]:
    """The tables a segment's shards are written to: the core ones and its kinds' own, ``jobs`` last (a segment
    is done once its ``jobs`` shard exists)."""
    own = {table for r in records for table in r.kind_rows}
    return [*(t for t in CORE_TABLES if t != "jobs"), *sorted(own), "jobs"]


class RunStore:
    """Results of one run directory, for one writer (held by a lock) or any number of readers."""

    def __init__(self, run_dir: Path) -> None:
        self.run_dir = run_dir
        self.journal_dir = run_dir / "journal"
        self.artifacts_dir = run_dir / "artifacts"
        self._lock: IO[bytes] | None = None
        self._segment: IO[bytes] | None = None
        self._segment_number = 0
        self._segment_rows = 0
        self.listener: StoreListener | None = None
        self.view: RemoteView | None = view_of(run_dir)

    def table_dir(self, table: str) -> Path:
        return self.run_dir / table

    # -- writing -------------------------------------------------------------------------

    def open_for_writing(self) -> None:
        """Take the run directory's lock and fold leftovers of a crashed run into shards."""
        try:
            self._open_for_writing()
        except OSError as exc:
            self.close()
            raise unwritable(self.run_dir, exc) from exc
        except RunDirError:  # e.g. a corrupt journal: the lock is not kept by a store that cannot write
            self.close()
            raise

    def _open_for_writing(self) -> None:
        if self.view is not None:
            url = self.view.location.url
            raise RunDirError(f"{url}: a remote run is written only by `scratchworld run` (output: URL)")
        self.run_dir.mkdir(parents=True, exist_ok=True)
        lock = (self.run_dir / ".lock").open("ab")
        try:
            fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            lock.close()
            raise RunDirError(f"{self.run_dir}: another scratchworld run is writing here") from None
        self._lock = lock
        for table in CORE_TABLES:
            self.table_dir(table).mkdir(exist_ok=True)
        self.journal_dir.mkdir(exist_ok=True)
        for number, path in self._segments():
            self._compact(number, path)
        self._segment_number = self._last_number()

    def commit(self, record: JobRecord) -> None:
        """Make one attempt durable; after this returns, a driver crash cannot lose it."""
        if self._lock is None:
            raise RuntimeError("open_for_writing() first")
        try:
            self._append(record)
        except OSError as exc:  # e.g. the disk filled up: stop with what is committed so far
            raise unwritable(self.run_dir, exc) from exc

    def _append(self, record: JobRecord) -> None:
        if self._segment is None:
            self._segment_number += 1
            self._segment = self._segment_path(self._segment_number).open("ab")
            self._segment_rows = 0
        line = record.model_dump_json().encode()
        self._segment.write(line + b"\n")
        self._segment.flush()
        self._segment_rows += 1
        if self.listener is not None:
            self.listener.committed(self._segment_number, self._segment_rows, line)
        if self._segment_rows >= SEGMENT_ROWS:
            self.flush()

    def write_artifact(self, job_id: str, attempt: int, name: str, data: bytes) -> str:
        """Store one file of an attempt; returns its folder relative to the run directory."""
        folder = self.artifacts_dir / job_id / f"attempt-{attempt}"
        try:
            (folder / name).parent.mkdir(parents=True, exist_ok=True)
            write_atomic(folder / name, data, sync=False)  # survives the driver's death; shards are synced
        except OSError as exc:
            raise unwritable(self.run_dir, exc) from exc
        self._stored(folder / name)
        return str(folder.relative_to(self.run_dir))

    def write_shared_image(self, path: str, data: bytes) -> None:
        """Store an image many jobs show (``path`` from ``shared_image_path``), once: an existing one is kept."""
        target = self.run_dir / path
        if target.is_file():
            return
        try:
            target.parent.mkdir(parents=True, exist_ok=True)
            write_atomic(target, data, sync=False)
        except OSError as exc:
            raise unwritable(self.run_dir, exc) from exc
        self._stored(target)

    def link_artifact(self, job_id: str, attempt: int, name: str, source: Path) -> str:
        """Store an existing file as one of an attempt's (a hard link when the file system allows, else a
        copy); returns its folder relative to the run directory."""
        folder = self.artifacts_dir / job_id / f"attempt-{attempt}"
        try:
            (folder / name).parent.mkdir(parents=True, exist_ok=True)
            link_atomic(source, folder / name)
        except OSError as exc:
            raise unwritable(self.run_dir, exc) from exc
        self._stored(folder / name)
        return str(folder.relative_to(self.run_dir))

    def _stored(self, path: Path) -> None:
        if self.listener is not None:
            self.listener.stored(str(path.relative_to(self.run_dir)))

    def flush(self) -> None:
        """Compact the open segment into shards."""
        if self._segment is None:
            return
        self._segment.close()
        self._segment = None
        try:
            self._compact(self._segment_number, self._segment_path(self._segment_number))
        except OSError as exc:  # the journal segment stays; the next open compacts it
            raise unwritable(self.run_dir, exc) from exc

    def close(self) -> None:
        self.flush()
        if self._lock is not None:
            self._lock.close()
            self._lock = None

    def _compact(self, number: int, path: Path) -> None:
        records = _read_segment(path)
        tables = _segment_tables(records) if records else []
        for table in tables:
            shard = _to_table(records, table)
            sink = pa.BufferOutputStream()
            pq.write_table(shard, sink, compression="zstd")
            self.table_dir(table).mkdir(exist_ok=True)
            write_atomic(self.table_dir(table) / f"part-{number:06d}.parquet", sink.getvalue().to_pybytes())
        path.unlink()
        if self.listener is not None and tables:
            self.listener.compacted(number, tables)

    def _segment_path(self, number: int) -> Path:
        return self.journal_dir / f"segment-{number:06d}.jsonl"

    def _segments(self) -> list[tuple[int, Path]]:
        found = []
        for path in self.journal_dir.iterdir() if self.journal_dir.exists() else []:
            match = _SEGMENT.match(path.name)
            if match:
                found.append((int(match.group(1)), path))
        return sorted(found)

    def _parts(self, table: str) -> dict[int, str]:
        """The table's shards by segment number: files here, or objects in the bucket for a view."""
        if self.view is not None:
            return self.view.parts(table)
        folder = self.table_dir(table)
        found: dict[int, str] = {}
        for path in folder.iterdir() if folder.exists() else []:
            match = _PART.match(path.name)
            if match:
                found[int(match.group(1))] = str(path)
        return found

    def _last_number(self) -> int:
        return max([n for n, _ in self._segments()] + list(self._parts("jobs")), default=0)

    # -- reading -------------------------------------------------------------------------

    def read_table(self, table: str, columns: list[str] | None = None) -> pa.Table:
        """All rows of a table: compacted shards plus the journal not yet compacted.

        Each segment counts once: as its shards when its ``jobs`` shard exists (written last),
        else as journal lines, so a crash or a compaction in progress never doubles rows.
        """
        for _ in range(2):
            try:
                return self._read_table(table, columns)
            except FileNotFoundError:
                continue  # the writer compacted a segment between listing and reading it: look again
        return self._read_table(table, columns)

    def _read_table(self, table: str, columns: list[str] | None) -> pa.Table:
        schema = table_schema(table)
        parts: list[pa.Table] = []
        folder = self.table_dir(table)
        segments = self._segments()  # listed before the shards: a segment gone by then has its jobs shard
        done = set(self._parts("jobs"))
        files = [path for n, path in sorted(self._parts(table).items()) if n in done]
        filesystem = self.view.fs if self.view is not None else None
        for path in files:
            _check_shard(path, table, filesystem)
        if files:
            try:
                dataset = ds.dataset(files, schema=schema, format="parquet", filesystem=filesystem)
                parts.append(dataset.to_table(columns=columns))
            except (OSError, pa.ArrowInvalid) as exc:
                raise RunDirError(f"{folder}: unreadable shard: {exc}") from exc
        pending = [r for n, path in segments if n not in done for r in _read_segment(path)]
        if pending:
            journal = _to_table(pending, table)
            parts.append(journal.select(columns) if columns else journal)
        if not parts:
            empty = schema.empty_table()
            return empty.select(columns) if columns else empty
        return pa.concat_tables(parts)

    def job_rows(self) -> list[JobRow]:
        """Every attempt's job row; rows of shards older than schema 4 get the run's kind as ``benchmark``."""
        rows = self.read_table("jobs").to_pylist()
        if any(row["benchmark"] is None for row in rows):
            kind = kind_of_run(self.run_dir, self).name
            rows = [row if row["benchmark"] is not None else {**row, "benchmark": kind} for row in rows]
        try:
            return [JobRow.model_validate(row) for row in rows]
        except ValidationError as exc:
            raise RunDirError(
                f"{self.table_dir('jobs')}: a row is not a job of a run: {validation_summary(exc)}"
            ) from exc

    def cost_usd(self) -> float:
        """Model spend of every attempt recorded here."""
        column = self.read_table("jobs", columns=["cost_usd"]).column("cost_usd").to_pylist()
        return float(sum(value or 0.0 for value in column))

    def undecided(self, jobs: Iterable[_Job]) -> list[tuple[_Job, int]]:
        """The ``jobs`` with no verdict here yet, each with the attempt number it runs as next (resume)."""
        attempts = self.attempts()
        todo = []
        for job in jobs:
            last, decided = attempts.get(job.job_id, (0, False))
            if not decided:
                todo.append((job, last + 1))
        return todo

    def attempts(self) -> dict[str, tuple[int, bool]]:
        """Per job id: the highest attempt number recorded, and whether any attempt has a verdict."""
        table = self.read_table("jobs", columns=["job_id", "attempt", "outcome"])
        found: dict[str, tuple[int, bool]] = {}
        for job, attempt, outcome in zip(*(table.column(c).to_pylist() for c in table.column_names), strict=True):
            last, decided = found.get(job, (0, False))
            found[job] = (max(last, attempt), decided or outcome != "error")
        return found


def effective_rows(rows: list[JobRow]) -> Iterator[JobRow]:
    """One row per job: its latest attempt with a verdict, else its latest error.

    Ray may deliver a job twice and resume re-runs errors, so the tables can hold several
    attempts of one job; reports count each job once through this view.
    """
    best: dict[str, JobRow] = {}
    for row in rows:
        current = best.get(row.job_id)
        if current is None or _rank(row) > _rank(current):
            best[row.job_id] = row
    yield from best.values()


def _rank(row: JobRow) -> tuple[bool, int]:
    return (row.outcome != "error", row.attempt)


def kind_of_run(run_dir: Path, store: RunStore | None = None) -> KindRows:
    """The kind a run directory holds: as its rows name it; in a run without rows of schema 4 or later, the
    first kind that claims it (``holds``: by its own tables, or its manifest), the default kind last."""
    store = store or RunStore(run_dir)
    column = store.read_table("jobs", columns=["benchmark"]).column("benchmark")
    named = sorted({name for name in column.to_pylist() if name is not None})
    if len(named) > 1:
        raise RunDirError(f"{run_dir}: holds jobs of several benchmarks ({', '.join(named)}); a run holds one")
    if named:
        try:
            return job_kind(named[0], KindRows)
        except UnknownKindError as exc:
            raise RunDirError(f"{run_dir}: {exc}") from None
    default = job_kind(DEFAULT_KIND, KindRows)
    return next((kind for kind in job_kinds(KindRows) if kind is not default and kind.holds(run_dir)), default)
