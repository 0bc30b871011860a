"""The run a regrade reads: each job at its effective attempt, and the final project that attempt stored."""

from __future__ import annotations

import hashlib
from collections import defaultdict
from pathlib import Path

from pydantic import BaseModel, ConfigDict

from scratchworld_dist._errors import RunDirError
from scratchworld_dist.results import (
    JobRow,
    RunManifest,
    RunStore,
    StepRow,
    effective_rows,
    kind_of_run,
    local_folder,
    require_manifest,
)

FINAL_PROJECT = "final.sb3"


class SourceJob(BaseModel):
    """One job of the source run whose effective attempt left a project to evaluate again."""

    model_config = ConfigDict(frozen=True)

    row: JobRow
    artifacts: Path
    """The attempt's artifact folder (absolute): ``final.sb3``, ``trajectory.jsonl``, ``images/``."""

    project_sha256: str


class SourceRun(BaseModel):
    """A run directory as a regrade sees it."""

    path: Path
    manifest: RunManifest
    jobs: list[SourceJob]
    without_project: list[JobRow]
    """Effective rows whose attempt stored no final project (e.g. an error before the editor opened)."""

    steps: dict[str, list[StepRow]]
    """The agent's steps of each source job's effective attempt, by source job id."""


def read_source(path: Path) -> SourceRun:
    """The source run's jobs at their effective attempts (rows of its manifest's suite and harness only)."""
    manifest = require_manifest(path)
    store = RunStore(path)
    rows = manifest.current_rows(store.job_rows())
    refusal = kind_of_run(path).regrade_refusal
    if refusal is not None:
        raise RunDirError(f"{path}: {refusal}")
    if not rows:
        raise RunDirError(f"{path}: no job results of its suite and harness to regrade")
    jobs, without = [], []
    artifacts = (path / "artifacts").resolve()
    for row in sorted(effective_rows(rows), key=lambda r: (r.task_id, r.mode, r.seed, r.job_id)):
        folder = local_folder(path, row.artifact_dir).resolve() if row.artifact_dir else None  # remote: fetched
        if folder is not None and not folder.is_relative_to(artifacts):
            raise RunDirError(f"{path}: job {row.job_id} names artifacts outside the run ({row.artifact_dir})")
        if folder is None or not (folder / FINAL_PROJECT).is_file():
            without.append(row)
            continue
        digest = hashlib.sha256()
        with (folder / FINAL_PROJECT).open("rb") as handle:
            while chunk := handle.read(1 << 20):
                digest.update(chunk)
        jobs.append(SourceJob(row=row, artifacts=folder, project_sha256=digest.hexdigest()))
    if not jobs:
        raise RunDirError(f"{path}: none of its {len(without)} job(s) stored a final project: nothing to regrade")
    return SourceRun(
        path=path.resolve(), manifest=manifest, jobs=jobs, without_project=without, steps=_steps(store, jobs)
    )


def _steps(store: RunStore, jobs: list[SourceJob]) -> dict[str, list[StepRow]]:
    wanted = {(job.row.job_id, job.row.attempt) for job in jobs}
    steps: dict[str, list[StepRow]] = defaultdict(list)
    for record in store.read_table("steps").to_pylist():
        if (record["job_id"], record["attempt"]) in wanted:
            steps[record["job_id"]].append(StepRow.model_validate(record))
    return {job: sorted(rows, key=lambda s: s.step) for job, rows in steps.items()}
