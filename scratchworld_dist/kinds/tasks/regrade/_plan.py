"""Planning a regrade: the source's projects against the tasks of a suite, each job named by what decides it.

A regrade job's id hashes the source job and attempt, the project's bytes, the new task content (its
evaluation script included), profile, clock, project limits and the harness: regrading again under the
same conditions resumes, and any change is a new job, never a reused verdict.
"""

from __future__ import annotations

from pathlib import Path

from pydantic import BaseModel, ConfigDict

from scratchworld_dist._errors import TaskNotFoundError
from scratchworld_dist._files import FileTooLargeError, read_file
from scratchworld_dist.kinds.tasks._plan import TaskContent, read_task
from scratchworld_dist.kinds.tasks.regrade._source import FINAL_PROJECT, SourceJob, SourceRun
from scratchworld_dist.suites import load_suite, stability_marks
from scratchworld_dist.sweep import Limits, SuiteInfo, identity_id, suite_hash
from workers.contract import (
    MIB,
    EvaluationClock,
    EvaluationPage,
    EvaluationProfile,
    EvaluationRender,
    HarnessFingerprint,
    ProjectLimits,
    evaluation_seed,
)
from workers.kinds.tasks import RegradeSpec


class RegradeJob(BaseModel):
    """One source job's project, to be evaluated against its task's new content."""

    model_config = ConfigDict(frozen=True)

    job_id: str
    source: SourceJob
    task_hash: str
    project_limits: ProjectLimits
    harness: str

    @property
    def task_id(self) -> str:
        return self.source.row.task_id

    def worker_job(self, attempt: int, timeout_s: float) -> RegradeSpec:
        """What the worker is sent: the project read now (only the jobs in flight hold theirs)."""
        return RegradeSpec(
            job_id=self.job_id,
            attempt=attempt,
            task_id=self.task_id,
            project=_read_project(self.source.artifacts / FINAL_PROJECT, self.project_limits),
            timeout_s=timeout_s,
            project_limits=self.project_limits,
            harness=self.harness,
            evaluation_seed=evaluation_seed(self.task_id, self.source.row.seed),
        )


def _read_project(path: Path, limits: ProjectLimits) -> bytes:
    """The project, or, for one over the size limit, just enough of it for the worker to refuse it as
    ``project_too_large`` (as the episode's own evaluation did) without holding all of it."""
    limit = int(limits.max_file_mb * MIB)
    try:
        return read_file(path, limit)
    except FileTooLargeError:
        with path.open("rb") as handle:
            return handle.read(limit + 1)


class RegradePlan(BaseModel):
    """A regrade resolved against its suite and this harness."""

    source: SourceRun
    harness: HarnessFingerprint
    suite: SuiteInfo
    profile: EvaluationProfile
    clock: EvaluationClock
    render: EvaluationRender
    page: EvaluationPage = "bare"
    contents: list[TaskContent]
    jobs: list[RegradeJob]
    limits: Limits
    """The source sweep's execution limits (timeout, retries, slots, memory reserve)."""

    project_limits: ProjectLimits


def regrade_job_id(
    source: SourceJob,
    task_hash: str,
    profile: EvaluationProfile,
    clock: EvaluationClock,
    limits: ProjectLimits,
    harness: str,
) -> str:
    """The regrade's name: a hash of everything that can change its verdict."""
    identity = {
        "regrade": [source.row.job_id, source.row.attempt, source.project_sha256],
        "task": [source.row.task_id, task_hash],
        "profile": profile,
        "clock": clock,
        "project_limits": limits.model_dump(mode="json"),
        "harness": harness,
    }
    return identity_id(identity)


def plan_regrade(
    source: SourceRun,
    harness: HarnessFingerprint,
    suite_dir: Path | None = None,
    profile: EvaluationProfile | None = None,
    clock: EvaluationClock | None = None,
    render: EvaluationRender | None = None,
    page: EvaluationPage | None = None,
) -> RegradePlan:
    """The source's projects against ``suite_dir`` (default: the source's suite) under ``profile``,
    ``clock``, ``render`` and ``page`` (default: the source sweep's, else the suite's own defaults)."""
    config = source.manifest.config
    suite = load_suite(suite_dir or Path(source.manifest.suite.root))
    known = {task.id for task in suite.tasks}
    needed = sorted({job.row.task_id for job in source.jobs})
    missing = [task_id for task_id in needed if task_id not in known]
    if missing:
        shown = ", ".join(missing[:10]) + (f" (and {len(missing) - 10} more)" if len(missing) > 10 else "")
        raise TaskNotFoundError(f"{suite.root}: suite {suite.name} lacks task(s) of {source.path}: {shown}")
    limits = ProjectLimits.model_validate(config.get("project_limits") or {})
    profile = profile or config.get("profile")
    clock = clock or config.get("clock")
    render = render or config.get("render")
    page = page or config.get("evaluation_page")
    contents = {
        task_id: read_task(suite.task(task_id), profile, clock, limits, render, page=page) for task_id in needed
    }
    specs = [content.payload.evaluation for content in contents.values()]
    resolved_profile = specs[0].profile if specs else (profile or "native")
    resolved_clock = specs[0].clock if specs else (clock or "virtual")
    jobs = [
        RegradeJob(
            job_id=regrade_job_id(
                job, contents[job.row.task_id].task_hash, resolved_profile, resolved_clock, limits, harness.digest
            ),
            source=job,
            task_hash=contents[job.row.task_id].task_hash,
            project_limits=limits,
            harness=harness.digest,
        )
        for job in source.jobs
    ]
    info = SuiteInfo(
        name=suite.name,
        kind=suite.kind,
        root=str(suite.root),
        hash=suite_hash(contents.values()),
        tasks=len(needed),
        stability=stability_marks(suite, [suite.task(task_id) for task_id in needed]),
    )
    return RegradePlan(
        source=source,
        harness=harness,
        suite=info,
        profile=resolved_profile,
        clock=resolved_clock,
        render=specs[0].render if specs else (render or "on_demand"),
        page=specs[0].page if specs else (page or "bare"),
        contents=list(contents.values()),
        jobs=jobs,
        limits=_limits(config.get("limits") or {}),
        project_limits=limits,
    )


def _limits(raw: dict[str, object]) -> Limits:
    """The source sweep's limits, reading only the fields this version knows."""
    return Limits.model_validate({key: value for key, value in raw.items() if key in Limits.model_fields})
