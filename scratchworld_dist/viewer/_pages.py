"""Each page of the viewer as data for its template: the runs, a run, its jobs, one job, a comparison.

A page reads the run directories when it is built, so the server shows a run in progress as it
stands at each refresh, and the static export is the same pages built once.
"""

from __future__ import annotations

import json
from collections import Counter
from typing import Literal

from pydantic import BaseModel, JsonValue

from scratchworld_dist._errors import RunDirError
from scratchworld_dist.results import VIDEO_FILE, JobRow
from scratchworld_dist.suites import StabilityMarks
from scratchworld_dist.sweep import stored_section
from scratchworld_dist.viewer._kind import AttemptPanel
from scratchworld_dist.viewer._listing import project_listing
from scratchworld_dist.viewer._runs import Attempt, ViewedRun
from scratchworld_dist.viewer._timeline import StepView, step_views
from scratchworld_dist.viewer._video import VideoView, video_view

JOB_COLUMNS = (
    "job_id",
    "attempt",
    "model",
    "mode",
    "agent",
    "category",
    "task_id",
    "seed",
    "setting",
    "outcome",
    "error_class",
    "tests_passed",
    "tests_total",
    "psr",
    "steps",
    "cost_usd",
    "episode_s",
    "finished_at",
    "error_message",
)
"""The columns of the jobs table's data, in order (``jobs.js`` reads them by name)."""


class RunCard(BaseModel):
    """A run as the runs page lists it."""

    index: int
    name: str
    path: str
    suite: str
    planned: int
    jobs: int
    outcomes: dict[str, int]
    in_progress: bool
    started: str | None
    finished: str | None
    harness: str


class ErrorLink(BaseModel):
    error_class: str
    jobs: int


class RunPage(BaseModel):
    card: RunCard
    warnings: list[str]
    report_html: str
    """The report's tables, already escaped HTML (the kind's ``KindPanel.report_html``)."""

    plots_html: str
    errors: list[ErrorLink]
    config: str
    packages: dict[str, str]
    harness_parts: int
    git_commit: str | None
    conditions: dict[str, str]
    sessions: list[SessionLine]
    unstable_note: str | None = None
    """One line naming the run's tasks with tests known to be unstable (None without stability data)."""


class TestLine(BaseModel):
    """One unit test of an attempt, as its table shows it."""

    __test__ = False
    name: str
    passed: Literal["pass", "fail"]
    message: str
    duration: str
    unstable: str | None = None
    """Set for a test known to be unstable when the run was planned: its note (what changes it, where it passes)."""


class SessionLine(BaseModel):
    """One ``scratchworld run`` (or regrade) on the run directory."""

    started: str
    finished: str
    host: str
    planned: int
    submitted: int
    nodes: int


class JobsData(BaseModel):
    """The jobs table's data: column names, and per job (its counted attempt) one list of values."""

    columns: list[str]
    rows: list[list[JsonValue]]


class AttemptView(BaseModel):
    row: JobRow
    steps: list[StepView]
    steps_note: str | None
    tests: list[TestLine]
    listing: str | None
    files: str | None
    """The attempt's artifact folder relative to the run's ``files/`` (None without artifacts)."""

    image_hrefs: dict[str, str]
    """Where each image its prompts showed is, by digest, relative to the job's page: the attempt's own
    ``images/``, or the run's shared ones (a perception item's screenshot)."""

    panel: AttemptPanel | None = None
    """What the run's kind shows of the attempt's own rows (a perception job's answer and scores)."""

    video: VideoView | None = None
    """The episode's video with its steps' marks, when the attempt was recorded (``record.video``)."""


class JobPage(BaseModel):
    run: RunCard
    job_id: str
    instruction: str | None
    attempts: list[AttemptView]
    """Newest first; the job's verdict is the effective one (``effective``)."""

    effective: int
    """Index in ``attempts`` of the attempt the reports count."""


def run_card(index: int, run: ViewedRun, rows: list[JobRow] | None = None) -> RunCard:
    manifest = run.manifest()
    if manifest is None:
        raise RunDirError(f"{run.path}: the manifest is gone")
    effective = run.effective_rows() if rows is None else rows
    sessions = manifest.sessions
    return RunCard(
        index=index,
        name=manifest.run_name,
        path=str(run.path),
        suite=f"{manifest.suite.name} ({manifest.suite.tasks} tasks, hash {manifest.suite.hash})",
        planned=manifest.planned_jobs,
        jobs=len(effective),
        outcomes=dict(Counter(r.outcome for r in effective)),
        in_progress=bool(sessions) and sessions[-1].finished_at is None,
        started=_time(manifest.started_at),
        finished=_time(manifest.finished_at),
        harness=manifest.harness.digest if manifest.harness else "-",
    )


def run_page(index: int, run: ViewedRun, plots_html: str) -> RunPage:

    manifest = run.manifest()
    if manifest is None:
        raise RunDirError(f"{run.path}: the manifest is gone")
    effective = run.effective_rows()
    warnings: list[str] = []
    report_html = "<p>No job has finished yet.</p>"
    if effective:
        report_html, warnings = run.kind().report_html(run.path)
    errors = Counter(r.error_class or "unknown" for r in effective if r.outcome == "error")
    config = manifest.config
    clock = stored_section(config, "tasks").get("episode_clock")  # manifests of older code: a top-level key
    conditions = {
        "evaluation profile": str(config.get("profile") or "the suite's"),
        "evaluation clock": str(config.get("clock") or "the suite's"),
        "evaluation render": str(config.get("render") or "on_demand"),
        "evaluation page": str(config.get("evaluation_page") or "bare (the editor for a script that needs it)"),
        "evaluation timing": str(config.get("timing") or "the profile's (upstream in virtual time: calibrated)"),
    }
    if manifest.regrade is not None:  # the new verdicts' conditions, and what they re-evaluated
        regrade = manifest.regrade
        conditions = {
            "regrade of": f"{regrade.source_run_name} ({regrade.source_run}), harness {regrade.source_harness or '-'}",
            "evaluation profile": regrade.profile,
            "evaluation clock": regrade.clock,
            "evaluation render": regrade.render or "every_frame",
            "evaluation page": regrade.evaluation_page or "editor",
            "evaluation suite": f"{regrade.suite.name} ({regrade.suite.root}, hash {regrade.suite.hash})",
            "regraded jobs": f"{regrade.regraded_jobs} ({regrade.without_project} without a final project left out)",
        }
    conditions |= {
        "episode clock": json.dumps(clock) if clock else "the suite kind's default",
        "harness": manifest.harness.digest if manifest.harness else "-",
        "schema version": str(manifest.schema_version),
    }
    sessions = [
        SessionLine(
            started=_time(s.started_at) or "-",
            finished=_time(s.finished_at) or "killed or running",
            host=s.host,
            planned=s.planned,
            submitted=s.submitted,
            nodes=len(s.nodes),
        )
        for s in manifest.sessions
    ]
    return RunPage(
        card=run_card(index, run, effective),
        warnings=warnings,
        report_html=report_html,
        plots_html=plots_html,
        errors=[ErrorLink(error_class=c, jobs=n) for c, n in errors.most_common()],
        config=json.dumps(config, indent=2, sort_keys=True),
        packages=manifest.packages,
        harness_parts=len(manifest.harness.parts) if manifest.harness else 0,
        git_commit=manifest.git_commit,
        conditions=conditions,
        sessions=sessions,
        unstable_note=_unstable_note(manifest.suite.stability),
    )


def _unstable_note(marks: StabilityMarks | None) -> str | None:
    """The run page's line on known test stability: which tasks have unstable tests, and how many."""
    if marks is None:
        return None
    tasks = {task: len(tests) for task, tests in sorted(marks.unstable.items()) if tests}
    where = f"known test stability from {marks.source}, made {marks.made_on}"
    if not tasks:
        return f"No test of the {len(marks.checked)} checked task(s) is known to be unstable ({where})."
    named = ", ".join(f"{task} ({count} test{'s' * (count != 1)})" for task, count in tasks.items())
    return (
        f"Tasks with tests known to be unstable (their verdicts can change with frame timing or phase; {where}): "
        f"{named}. Their job pages mark those tests."
    )


def jobs_data(run: ViewedRun) -> JobsData:
    """The jobs table's data: one list per job (its effective attempt), and how many attempts it had."""
    rows = sorted(run.effective_rows(), key=lambda r: (r.task_id, r.mode, r.model, r.seed, r.job_id))
    attempts = Counter(r.job_id for r in {(r.job_id, r.attempt): r for r in run.rows()}.values())
    values: list[list[JsonValue]] = []
    for row in rows:
        dumped = row.model_dump(mode="json", include=set(JOB_COLUMNS))
        values.append([*(dumped.get(c) for c in JOB_COLUMNS), attempts[row.job_id]])
    return JobsData(columns=[*JOB_COLUMNS, "attempts"], rows=values)


def job_page(index: int, run: ViewedRun, job_id: str) -> JobPage | None:
    found = run.attempts(job_id)
    if not found:
        return None
    from scratchworld_dist.results import effective_rows

    (best,) = effective_rows([a.row for a in found])
    kind = run.kind()
    manifest = run.manifest()
    marks = manifest.suite.stability if manifest is not None else None
    notes = marks.unstable.get(found[0].row.task_id, {}) if marks is not None else {}
    views = [
        _attempt_view(run, attempt, kind.attempt_panel(attempt.kind_rows, "../", run.path), notes) for attempt in found
    ]
    own = next((v.panel.instruction for v in views if v.panel is not None and v.panel.instruction), None)
    return JobPage(
        run=run_card(index, run),
        job_id=job_id,
        instruction=own or run.instruction(found[0].row.task_id),
        attempts=views,
        effective=next(i for i, a in enumerate(found) if a.row.attempt == best.attempt),
    )


def _attempt_view(run: ViewedRun, attempt: Attempt, panel: AttemptPanel | None, notes: dict[str, str]) -> AttemptView:
    """``notes``: the run's notes on the task's unstable tests, by test name."""
    row = attempt.row
    listing, files, video = None, None, None
    if row.artifact_dir is not None:
        files = row.artifact_dir.removeprefix("artifacts/")
        final = run.artifact(f"{files}/final.sb3")
        if final is not None:
            listing = project_listing(final.read_bytes())
        recorded = run.artifact(f"{files}/{VIDEO_FILE}")
        video = video_view(recorded.parent if recorded is not None else None, files, attempt.steps)
    tests = [
        TestLine(
            name=t.name,
            passed="pass" if t.passed else "fail",
            message=t.error or "",
            duration="-" if t.duration_ms is None else f"{t.duration_ms:.0f} ms",
            unstable=notes.get(t.name, "known to be unstable") if t.unstable else None,
        )
        for t in attempt.tests
    ]
    steps = step_views(attempt.steps)
    hrefs: dict[str, str] = {}
    for digest in {d for step in steps for message in step.prompt for d in message.images}:
        if files is not None and run.artifact(f"{files}/images/{digest}.png") is not None:
            hrefs[digest] = f"../files/{files}/images/{digest}.png"
        elif run.shared_image(f"{digest}.png") is not None:
            hrefs[digest] = f"../images/{digest}.png"
    return AttemptView(
        row=row,
        steps=steps,
        steps_note=attempt.steps_note,
        tests=tests,
        listing=listing,
        files=files,
        image_hrefs=hrefs,
        panel=panel,
        video=video,
    )


def _time(value: object) -> str | None:
    return None if value is None else str(value)[:19].replace("T", " ")
