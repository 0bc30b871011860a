"""The programs an audit job evaluated, made again for its page: its task's golden and its variant.

A run keeps each variant's verdict and change, not its project.json (the plan holds it, and a plan is not
kept). Both programs are made again from the run's manifest, as its plan made them: the config it was
planned from, its suite, its harness. A job's id hashes its project's bytes, its task's and the harness, so a
program made again is shown only under the id it was evaluated under; when the suite or the audit's code
changed since, the page says so instead of showing another program.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any

from pydantic import ValidationError

from scratchworld_dist.kinds.audit._declarations import suite_declarations
from scratchworld_dist.kinds.audit._plan import DEFAULT_AGENT, AuditBody, AuditSweep, audit_jobs, evaluated_under
from scratchworld_dist.kinds.tasks import selected_tasks
from scratchworld_dist.results import read_manifest
from scratchworld_dist.sweep import SweepConfig
from workers.contract import ScratchWorldError


class ProgramsUnavailableError(Exception):
    """Why a job's programs cannot be shown (one line, for its page)."""


@dataclass(frozen=True)
class EvaluatedPrograms:
    golden: dict[str, Any]
    """The task's golden project.json."""

    variant: dict[str, Any] | None
    """The variant's project.json (None for the golden's own job)."""


def remade_programs(run_dir: Path, task_id: str, job_id: str) -> EvaluatedPrograms:
    """The golden and the variant job ``job_id`` of ``run_dir`` evaluated (else ``ProgramsUnavailableError``)."""
    manifest = read_manifest(run_dir)
    if manifest is None:
        raise ProgramsUnavailableError(f"{run_dir}: no manifest")
    if manifest.harness is None:
        raise ProgramsUnavailableError("the run records no harness: a program made again cannot be checked against it")
    bodies = _task_jobs(str(run_dir.resolve()), manifest.config_hash, manifest.harness.digest, task_id)
    body = bodies.get(job_id)
    golden = next((b for b in bodies.values() if b.variant == "golden"), None)
    if body is None or golden is None:
        raise ProgramsUnavailableError(
            "the task's golden or the audit's code changed since this job was planned: its variant is not made "
            "again (its change, as recorded, is below)"
        )
    variant = None if body.variant == "golden" else json.loads(body.project_json)
    return EvaluatedPrograms(golden=json.loads(golden.project_json), variant=variant)


@lru_cache(maxsize=8)
def _task_jobs(run_dir: str, config_hash: str, harness: str, task_id: str) -> dict[str, AuditBody]:
    """The jobs the run's plan made for one task, by id (a task's pages share one planning: milliseconds, and an
    export asks for every job's)."""
    manifest = read_manifest(Path(run_dir))
    if manifest is None or manifest.config_hash != config_hash:
        raise ProgramsUnavailableError(f"{run_dir}: the manifest changed while it was read")
    try:
        config = SweepConfig.model_validate(manifest.config)
        one = config.model_copy(
            update={"tasks": config.tasks.model_copy(update={"ids": [task_id], "categories": [], "limit": None})}
        )
        suite, contents = selected_tasks(evaluated_under(one), None)
        settings = config.section("audit", AuditSweep)
        if "stop_at_first_kill" not in (manifest.config.get("audit") or {}):  # planned before mutants could stop
            settings = settings.model_copy(update={"stop_at_first_kill": False})
        declarations = suite_declarations(suite, settings.explanations)
        jobs = audit_jobs(contents, settings, DEFAULT_AGENT, harness, config.project_limits, declarations)
        return {job.job_id: job.body for job in jobs if isinstance(job.body, AuditBody)}
    except (ScratchWorldError, ValidationError, OSError) as exc:
        first = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise ProgramsUnavailableError(f"the run's suite cannot be read as it was planned: {first}") from exc
