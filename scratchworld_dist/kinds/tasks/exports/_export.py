"""``scratchworld export``: task-episode runs in formats other tools read (a leaderboard, upstream's
submission, ATIF trajectories), each job counted at its effective attempt as the reports count it."""

from __future__ import annotations

import json
from collections import defaultdict
from collections.abc import Sequence
from importlib.metadata import version
from pathlib import Path
from typing import Any, Literal

from pydantic import BaseModel

from scratchworld_dist._errors import RunDirError, ScratchWorldError
from scratchworld_dist._files import write_atomic
from scratchworld_dist.kinds.tasks.exports._atif import ImageFiles, atif_trajectory, trajectory_file_name
from scratchworld_dist.kinds.tasks.exports._leaderboard import leaderboard_files
from scratchworld_dist.kinds.tasks.exports._submission import SubmissionLine, submission_file_name, submission_line
from scratchworld_dist.results import (
    JobRow,
    RunStore,
    StepRow,
    attempt_steps,
    effective_rows,
    kind_of_run,
    require_manifest,
)
from scratchworld_dist.suites import suite_instructions
from workers.contract import AgentUnavailableError, EpisodeClock, StepRecord

ExportFormat = Literal["leaderboard", "upstream-submission", "atif"]
EXPORT_FORMATS: tuple[ExportFormat, ...] = ("leaderboard", "upstream-submission", "atif")


class ExportSummary(BaseModel):
    files: list[Path]
    warnings: list[str]


def export_runs(run_dirs: Sequence[Path], fmt: ExportFormat, out: Path, *, force: bool = False) -> ExportSummary:
    """Write ``run_dirs`` in ``fmt`` under the folder ``out``; ``RunDirError`` for runs that are not episodes."""
    if not run_dirs:
        raise RunDirError("no run directory given")
    for run_dir in run_dirs:
        kind = kind_of_run(run_dir)
        if not getattr(kind, "episodes", False):
            raise RunDirError(f"{run_dir}: holds {kind.title} jobs; export writes task-episode runs")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ScratchWorldError(f"{out}: cannot create the export folder: {exc.strerror or exc}") from exc
    if fmt == "leaderboard":
        return _leaderboard(run_dirs, out, force)
    attempts = [(run_dir, row, steps) for run_dir in run_dirs for row, steps in _counted_attempts(run_dir)]
    if fmt == "upstream-submission":
        return _submission(attempts, out)
    return _atif(attempts, out)


def _leaderboard(run_dirs: Sequence[Path], out: Path, force: bool) -> ExportSummary:
    contents, warnings = leaderboard_files(run_dirs, force=force)
    files = [out / name for name in contents]
    for path in files:
        write_atomic(path, contents[path.name])
    return ExportSummary(files=files, warnings=warnings)


def _counted_attempts(run_dir: Path) -> list[tuple[JobRow, list[StepRecord]]]:
    """Each job's effective attempt in the run as it stands, with its steps."""
    manifest = require_manifest(run_dir)
    store = RunStore(run_dir)
    rows = list(effective_rows(manifest.current_rows(store.job_rows())))
    step_rows: dict[tuple[str, int], list[StepRow]] = defaultdict(list)
    for raw in store.read_table("steps").to_pylist():
        step_rows[(raw["job_id"], raw["attempt"])].append(StepRow.model_validate(raw))
    return [(row, attempt_steps(run_dir, row, step_rows[(row.job_id, row.attempt)])[0]) for row in rows]


def _submission(attempts: list[tuple[Path, JobRow, list[StepRecord]]], out: Path) -> ExportSummary:
    files: dict[str, dict[str, SubmissionLine]] = defaultdict(dict)
    warnings = []
    for run_dir, row, steps in attempts:
        lines = files[submission_file_name(row)]
        if row.task_id in lines:
            warnings.append(f"{run_dir}: {row.task_id} is in an earlier run of {submission_file_name(row)}: kept that")
            continue
        lines[row.task_id] = submission_line(row, steps)
    written = []
    for name, lines in sorted(files.items()):
        text = "".join(lines[task].model_dump_json() + "\n" for task in sorted(lines))
        write_atomic(out / name, text.encode())
        written.append(out / name)
    return ExportSummary(files=written, warnings=warnings)


def _configured_agent(config: dict[str, Any]) -> type | None:
    """The class of the agent a run's config names (None when it is not installed here: the default clock)."""
    from workers.agent_api import agent_class

    agent = config.get("agent")
    name = agent.get("name") if isinstance(agent, dict) else agent
    if not isinstance(name, str):
        return None
    try:
        return agent_class(name)
    except AgentUnavailableError:
        return None


def _atif(attempts: list[tuple[Path, JobRow, list[StepRecord]]], out: Path) -> ExportSummary:
    """One trajectory per attempt under ``OUT/<run name>/``, the screenshots they show in its ``images/``."""
    from scratchworld_dist.kinds.tasks import default_episode_clock

    ours = version("scratchworld-dist")
    manifests = {run_dir: require_manifest(run_dir) for run_dir in {run for run, _, _ in attempts}}
    written = []
    for run_dir, row, steps in attempts:
        manifest = manifests[run_dir]
        suite = manifest.suite
        instruction = suite_instructions(suite.root, suite.hash).get(row.task_id)
        stated = (manifest.config.get("episodes") or {}).get("episode_clock")
        clock = (
            EpisodeClock.model_validate(stated)
            if stated is not None
            else default_episode_clock(_configured_agent(manifest.config))
        )
        folder = out / row.run_name
        images = ImageFiles(run_dir, row.artifact_dir, folder)
        trajectory = atif_trajectory(
            row, steps, instruction, ours, suite=suite, clock=clock, images=images, tags=manifest.tags
        )
        path = folder / trajectory_file_name(row)
        path.parent.mkdir(parents=True, exist_ok=True)
        write_atomic(path, (json.dumps(trajectory.to_json_dict(), indent=2) + "\n").encode())
        written.append(path)
    return ExportSummary(files=written, warnings=[])
