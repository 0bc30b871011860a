"""Reading run directories for a report, and deciding whether their results may be merged.

Results are only comparable within one suite (same task contents) and one harness (same code
and editor, by fingerprint), so runs that differ in either are refused unless forced, and rows
left over from an older suite or harness inside a run (a run continued with ``--force``) are set
aside.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TypeVar

from pydantic import BaseModel, ValidationError

from scratchworld_dist._errors import RunDirError, validation_summary
from scratchworld_dist.results import JobRow, RunManifest, RunStore, TestRow, require_manifest
from workers.contract import describe_differences

RowT = TypeVar("RowT", bound=BaseModel)


@dataclass(frozen=True)
class LoadedRun:
    """One run directory: its manifest and its attempt rows of the manifest's suite."""

    path: Path
    manifest: RunManifest
    rows: list[JobRow]
    """Every attempt row whose suite hash matches the manifest (duplicates included)."""

    stale_rows: int
    """Rows whose suite hash or harness fingerprint differs from the manifest's: results of an older suite or code."""

    @property
    def name(self) -> str:
        return f"{self.manifest.run_name} ({self.path})"


def load_run(path: Path) -> LoadedRun:
    """Read one run directory; raises ``RunDirError`` when it is not one or holds no results."""
    manifest = require_manifest(path)
    rows = RunStore(path).job_rows()
    if not rows:
        raise RunDirError(f"{path}: no job results yet (run {manifest.run_name!r} has not finished any job)")
    current = manifest.current_rows(rows)
    return LoadedRun(path=path, manifest=manifest, rows=current, stale_rows=len(rows) - len(current))


def load_runs(run_dirs: Sequence[Path], *, force: bool) -> tuple[list[LoadedRun], list[str]]:
    """Each distinct run directory once (a directory named twice is one run), checked for merging.

    Returns the runs and the warnings of a forced merge; raises ``RunDirError`` as ``load_run`` and
    ``check_compatible`` do, and for an empty list.
    """
    if not run_dirs:
        raise RunDirError("no run directory given")
    unique: dict[Path, Path] = {}
    for path in run_dirs:
        unique.setdefault(path.resolve(), path)
    runs = [load_run(path) for path in unique.values()]
    return runs, check_compatible(runs, force=force)


def incompatibilities(runs: Sequence[LoadedRun]) -> list[str]:
    """How the runs differ in suite or harness: each difference that makes their numbers incomparable."""
    problems = []
    if len({run.manifest.suite.hash for run in runs}) > 1:
        values = ", ".join(f"{run.name}: {run.manifest.suite.hash}" for run in runs)
        problems.append(f"runs differ in suite hash ({values})")
    first = runs[0]
    for run in runs[1:]:
        ours, theirs = first.manifest.harness, run.manifest.harness
        if ours is None or theirs is None:
            if ours is not theirs:
                problems.append(f"{first.name} and {run.name} differ in harness (one has no fingerprint)")
        elif ours.digest != theirs.digest:
            problems.append(
                f"{first.name} and {run.name} differ in harness {ours.digest} / {theirs.digest} "
                f"(files: {describe_differences(ours, theirs)})"
            )
    return problems


def stale_warnings(runs: Sequence[LoadedRun]) -> list[str]:
    """One warning per run that holds rows of an older suite or harness (they are left out)."""
    return [f"{r.name}: {r.stale_rows} row(s) of an older suite or harness excluded" for r in runs if r.stale_rows]


def read_rows(run_dir: Path, table: str, model: type[RowT], noun: str) -> list[RowT]:
    """The rows of one of a run directory's tables as ``model`` (``RunDirError`` naming the table for a row that
    is not ``noun``)."""
    store = RunStore(run_dir)
    try:
        return [model.model_validate(row) for row in store.read_table(table).to_pylist()]
    except ValidationError as exc:
        raise RunDirError(f"{store.table_dir(table)}: a row is not {noun}: {validation_summary(exc)}") from exc


def tests_of_attempts(run_dirs: Iterable[Path], wanted: set[tuple[str, int]]) -> dict[tuple[str, int], list[TestRow]]:
    """The test rows of the ``wanted`` attempts (job id, attempt) in the runs at ``run_dirs``, by attempt."""
    found: dict[tuple[str, int], list[TestRow]] = {}
    for run_dir in run_dirs:
        for test in read_rows(run_dir, "tests", TestRow, "a test row"):
            if (test.job_id, test.attempt) in wanted:
                found.setdefault((test.job_id, test.attempt), []).append(test)
    return found


def check_compatible(runs: Sequence[LoadedRun], *, force: bool) -> list[str]:
    """Warnings for runs that differ in suite or harness; without ``force`` those raise instead."""
    problems = incompatibilities(runs)
    if problems and not force:
        raise RunDirError(f"refusing to merge incomparable results: {'; '.join(problems)}; use --force to merge anyway")
    return [f"merged anyway (--force): {p}; their numbers are not comparable" for p in problems]
