"""Reading run directories for a report, and deciding whether their results may be merged.

Results are only comparable within one suite (same task contents) and one harness version
(same verdict logic), so runs that differ in either are refused unless forced, and rows left
over from an older suite inside a run are set aside.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from scratchworld_dist._errors import RunDirError
from scratchworld_dist.results import MANIFEST_NAME, JobRow, RunManifest, RunStore, read_manifest


@dataclass(frozen=True)
class LoadedRun:
    """One run directory: its manifest and its attempt rows of the manifest's suite."""

    path: Path
    manifest: RunManifest
    rows: list[JobRow]
    """Every attempt row whose suite hash matches the manifest (duplicates included)."""

    stale_rows: int
    """Rows whose suite hash differs from the manifest's: results of an older suite."""

    @property
    def name(self) -> str:
        return f"{self.manifest.run_name} ({self.path})"


def load_run(path: Path) -> LoadedRun:
    """Read one run directory; raises ``RunDirError`` when it is not one or holds no results."""
    if not path.is_dir():
        raise RunDirError(f"{path}: no such run directory")
    manifest = read_manifest(path)
    if manifest is None:
        raise RunDirError(f"{path}: no {MANIFEST_NAME}; not a scratchworld run directory")
    rows = RunStore(path).job_rows()
    if not rows:
        raise RunDirError(f"{path}: no job results yet (run {manifest.run_name!r} has not finished any job)")
    current = [r for r in rows if r.suite_hash == manifest.suite.hash]
    return LoadedRun(path=path, manifest=manifest, rows=current, stale_rows=len(rows) - len(current))


def check_compatible(runs: Sequence[LoadedRun], *, force: bool) -> list[str]:
    """Warnings for runs that differ in suite or harness; without ``force`` those raise instead."""
    problems = []
    for what, value in (
        ("suite hash", lambda run: run.manifest.suite.hash),
        ("harness version", lambda run: run.manifest.harness_version),
    ):
        if len({value(run) for run in runs}) > 1:
            values = ", ".join(f"{run.name}: {value(run)}" for run in runs)
            problems.append(f"runs differ in {what} ({values})")
    if problems and not force:
        raise RunDirError(f"refusing to merge incomparable results: {'; '.join(problems)}; use --force to merge anyway")
    return [f"merged anyway (--force): {p}; their numbers are not comparable" for p in problems]


def jobs_per_group(manifest: RunManifest) -> int | None:
    """Planned jobs of each agent/model and mode (tasks x seeds), when the manifest's config says.

    The sweep plans models x modes x tasks x seeds; the product is checked against
    ``planned_jobs`` so that a config this cannot read yields ``None`` rather than a wrong count.
    """
    config = manifest.config
    seeds, modes, models = config.get("seeds"), config.get("modes"), config.get("models")
    if not isinstance(seeds, list) or not isinstance(modes, list) or not isinstance(models, list | None):
        return None
    per_group = manifest.suite.tasks * len(seeds)
    if max(len(models or []), 1) * len(modes) * per_group != manifest.planned_jobs:
        return None
    return per_group
