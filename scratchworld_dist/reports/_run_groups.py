"""Run directories sorted by benchmark: each benchmark's runs are loaded and checked for merging among themselves.

Runs of different benchmarks are never merged (their suites differ by nature); the diagnosis table puts
them side by side per model instead.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Literal

from scratchworld_dist._errors import RunDirError
from scratchworld_dist.reports._drag_table import is_drag_run, read_drag_rows
from scratchworld_dist.reports._perception_table import is_perception_run, read_perception_rows
from scratchworld_dist.reports._runs import LoadedRun, load_runs
from scratchworld_dist.results import DragRow, PerceptionRow

Benchmark = Literal["tasks", "drag", "perception"]
BENCHMARKS: tuple[Benchmark, ...] = ("tasks", "drag", "perception")
"""As a sweep config names them (``benchmark:``), in the order reports show them."""


@dataclass(frozen=True)
class RunGroup:
    """The runs of one benchmark, loaded and checked for merging."""

    benchmark: Benchmark
    runs: list[LoadedRun]
    warnings: list[str]
    """Those of a forced merge."""

    drags: list[DragRow] = field(default_factory=list)
    """A drag group's ``drags`` rows (read once, for the diagnosis and the drag report)."""

    answers: list[PerceptionRow] = field(default_factory=list)
    """A perception group's ``perception`` rows (read once, for the diagnosis and the perception report)."""

    @property
    def paths(self) -> list[Path]:
        return [run.path for run in self.runs]


def run_benchmark(run_dir: Path) -> Benchmark:
    """The benchmark a run directory holds.

    Drag runs are told by their rows, as before manifests named the benchmark (a run whose manifest says
    drag but whose jobs are episodes is reported as episodes); perception runs by their rows or manifest,
    so a run whose every call failed is still one.
    """
    if is_drag_run(run_dir):
        return "drag"
    if is_perception_run(run_dir):
        return "perception"
    return "tasks"


def paths_by_benchmark(run_dirs: Sequence[Path]) -> dict[Benchmark, list[Path]]:
    """Each distinct run directory once (named twice is one run), under its benchmark, in ``BENCHMARKS`` order."""
    if not run_dirs:
        raise RunDirError("no run directory given")
    unique: dict[Path, Path] = {}
    for path in run_dirs:
        unique.setdefault(path.resolve(), path)
    found: dict[Benchmark, list[Path]] = {}
    for path in unique.values():
        found.setdefault(run_benchmark(path), []).append(path)
    return {benchmark: found[benchmark] for benchmark in BENCHMARKS if benchmark in found}


def load_groups(paths: dict[Benchmark, list[Path]], *, force: bool) -> list[RunGroup]:
    """Each benchmark's runs loaded and checked for merging (``RunDirError`` as ``load_runs`` raises it)."""
    groups = []
    for benchmark, members in paths.items():
        runs, warnings = load_runs(members, force=force)
        drags = [d for run in runs for d in read_drag_rows(run.path)] if benchmark == "drag" else []
        answers = [a for run in runs for a in read_perception_rows(run.path)] if benchmark == "perception" else []
        groups.append(RunGroup(benchmark=benchmark, runs=runs, warnings=warnings, drags=drags, answers=answers))
    return groups
