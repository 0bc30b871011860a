"""What the viewer reads of a run directory: its manifest, its job rows, and one job's whole record.

Everything is read again on each call, from shards and journal alike, so a page refreshed while a
run is in progress shows the jobs finished since. Trajectories are read from the attempt's
artifacts (they hold what the Parquet ``steps`` table drops: observations, prompts, replies, data);
an attempt without one falls back to its ``steps`` rows.
"""

from __future__ import annotations

import contextlib
import re
from collections import defaultdict
from pathlib import Path
from typing import TypeVar

import pyarrow.compute as pc
from pydantic import BaseModel, Field, SerializeAsAny

from scratchworld_dist.kinds import job_kind
from scratchworld_dist.results import (
    MANIFEST_NAME,
    JobRow,
    RunManifest,
    RunStore,
    StepRow,
    TestRow,
    attempt_steps,
    kind_of_run,
    local_file,
    local_folder,
    read_manifest,
    require_manifest,
)
from scratchworld_dist.results import effective_rows as effective
from scratchworld_dist.viewer._kind import KindPanel
from workers.contract import StepRecord

ARTIFACTS = "artifacts"
SHARED_IMAGES = "images"
_IMAGE_NAME = re.compile(r"[0-9a-f]{64}\.png")

_Row = TypeVar("_Row", bound=BaseModel)


class Attempt(BaseModel):
    """One attempt of a job as its page shows it."""

    row: JobRow
    steps: list[StepRecord]
    steps_note: str | None = None
    """Why the steps are partial or missing (no trajectory kept, an unreadable line)."""

    tests: list[TestRow]
    kind_rows: dict[str, list[SerializeAsAny[BaseModel]]] = Field(default_factory=dict)
    """Its rows in the tables of the run's kind (``drags``, ``perception``...), by table."""


class ViewedRun:
    """One run directory, read on demand."""

    def __init__(self, path: Path) -> None:
        require_manifest(path)
        self.path = path
        self.store = RunStore(path)
        self._rows: tuple[tuple[tuple[str, int, int], ...], list[JobRow]] | None = None

    def manifest(self) -> RunManifest | None:
        return read_manifest(self.path)

    def version(self) -> tuple[tuple[str, int, int], ...]:
        """What the run's rows are read from, as (name, size, mtime): equal versions hold equal rows."""
        files = [self.path / MANIFEST_NAME]
        for folder in (self.path / "jobs", self.path / "journal"):
            files += sorted(folder.iterdir()) if folder.is_dir() else []
        found = []
        for file in files:
            with contextlib.suppress(FileNotFoundError):  # compacted away meanwhile: the next look sees it
                stat = file.stat()
                found.append((f"{file.parent.name}/{file.name}", stat.st_size, stat.st_mtime_ns))
        return tuple(found)

    def rows(self) -> list[JobRow]:
        """Every attempt row of the run as it stands (stale rows of an older suite or harness left out).

        Read again only when the run's files changed since the last read (a refresh of a finished run's
        pages costs a directory listing; a run in progress is read anew as it commits).
        """
        version = self.version()
        if self._rows is not None and self._rows[0] == version:
            return self._rows[1]
        manifest = self.manifest()
        rows = self.store.job_rows()
        if manifest is not None:
            rows = manifest.current_rows(rows)
        self._rows = (version, rows)
        return rows

    def kind(self) -> KindPanel:
        """The kind of jobs the run holds (the default kind for a run with no rows yet)."""
        return job_kind(kind_of_run(self.path).name, KindPanel)

    def effective_rows(self) -> list[JobRow]:
        """One row per job: its latest attempt with a verdict, else its latest error."""
        return list(effective(self.rows()))

    def attempts(self, job_id: str) -> list[Attempt]:
        """Every attempt of ``job_id``, newest first (empty for a job the run does not hold)."""
        rows = {r.attempt: r for r in self.rows() if r.job_id == job_id}  # an attempt committed twice is one
        if not rows:
            return []
        tests = self._rows_of("tests", TestRow, job_id)
        step_rows = self._rows_of("steps", StepRow, job_id)
        own = {table: self._rows_of(table, model, job_id) for table, model in self.kind().tables.items()}
        found = []
        for attempt in sorted(rows, reverse=True):
            steps, note = attempt_steps(self.path, rows[attempt], step_rows.get(attempt, []))
            found.append(
                Attempt(
                    row=rows[attempt],
                    steps=steps,
                    steps_note=note,
                    tests=sorted(tests.get(attempt, []), key=lambda t: t.test_index),
                    kind_rows={table: by_attempt.get(attempt, []) for table, by_attempt in own.items()},
                )
            )
        return found

    def artifact(self, relative: str) -> Path | None:
        """The file ``relative`` names under the run's artifacts, or None if it is not one (or escapes them)."""
        root = (self.path / ARTIFACTS).resolve()
        local_file(self.path, f"{ARTIFACTS}/{relative}")  # a remote run's file is fetched when first shown
        try:
            target = (root / relative).resolve()
        except (OSError, ValueError):
            return None
        if not target.is_relative_to(root) or not target.is_file():
            return None
        return target

    def shared_image(self, name: str) -> Path | None:
        """An image the run keeps once for many jobs (``images/<sha256>.png``), or None if ``name`` is not one."""
        if not _IMAGE_NAME.fullmatch(name):
            return None
        path = local_file(self.path, f"{SHARED_IMAGES}/{name}")
        return path if path.is_file() else None

    def shared_images(self) -> list[Path]:
        folder = local_folder(self.path, SHARED_IMAGES)
        return sorted(p for p in folder.iterdir() if _IMAGE_NAME.fullmatch(p.name)) if folder.is_dir() else []

    def instruction(self, task_id: str) -> str | None:
        """The task's instruction from the run's suite, if that suite is still where the run found it."""
        manifest = self.manifest()
        if manifest is None:
            return None
        from scratchworld_dist.suites import suite_instructions

        return suite_instructions(manifest.suite.root, manifest.suite.hash).get(task_id)

    def _rows_of(self, table: str, model: type[_Row], job_id: str) -> dict[int, list[_Row]]:
        data = self.store.read_table(table)
        picked = data.filter(pc.equal(data.column("job_id"), job_id)).to_pylist()
        by_attempt: dict[int, list[_Row]] = defaultdict(list)
        for row in picked:
            by_attempt[row["attempt"]].append(model.model_validate(row))
        return by_attempt
