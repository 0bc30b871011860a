"""Run directories sorted by benchmark: each benchmark's runs are loaded and checked for merging among themselves.

Runs of different benchmarks are never merged (their suites differ by nature); the diagnosis table puts
them side by side per model instead.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

from pydantic import BaseModel

from scratchworld_dist._errors import RunDirError
from scratchworld_dist.kinds import job_kind, kind_names
from scratchworld_dist.reports._runs import LoadedRun, load_runs, read_rows
from scratchworld_dist.results import kind_of_run


@dataclass(frozen=True)
class RunGroup:
    """The runs of one benchmark, loaded and checked for merging."""

    benchmark: str
    runs: list[LoadedRun]
    warnings: list[str]
    """Those of a forced merge."""

    tables: dict[str, list[BaseModel]] = field(default_factory=dict)
    """The rows of the kind's own tables (``drags``, ``perception``...) over all its runs, read once."""

    @property
    def paths(self) -> list[Path]:
        return [run.path for run in self.runs]


def run_benchmark(run_dir: Path) -> str:
    """The benchmark a run directory holds (see ``kinds.kind_of_run``)."""
    return kind_of_run(run_dir).name


def paths_by_benchmark(run_dirs: Sequence[Path]) -> dict[str, list[Path]]:
    """Each distinct run directory once (named twice is one run), under its benchmark, in the kinds' order."""
    if not run_dirs:
        raise RunDirError("no run directory given")
    unique: dict[Path, Path] = {}
    for path in run_dirs:
        unique.setdefault(path.resolve(), path)
    found: dict[str, list[Path]] = {}
    for path in unique.values():
        found.setdefault(run_benchmark(path), []).append(path)
    return {benchmark: found[benchmark] for benchmark in kind_names() if benchmark in found}


def load_groups(paths: dict[str, list[Path]], *, force: bool) -> list[RunGroup]:
    """Each benchmark's runs loaded and checked for merging (``RunDirError`` as ``load_runs`` raises it)."""
    groups = []
    for benchmark, members in paths.items():
        runs, warnings = load_runs(members, force=force)
        tables: dict[str, list[BaseModel]] = {
            table: [row for run in runs for row in read_rows(run.path, table, model, f"a {table} row")]
            for table, model in job_kind(benchmark).tables.items()
        }
        groups.append(RunGroup(benchmark=benchmark, runs=runs, warnings=warnings, tables=tables))
    return groups
