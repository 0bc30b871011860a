"""The grader audit (``benchmark: audit``): variants of each task's golden project (mutants, which sound tests
fail, and refactorings, which they pass) evaluated by the task's own tests; no agent acts, no model is called."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from types import MappingProxyType
from typing import ClassVar

from pydantic import BaseModel

from scratchworld_dist.kinds.audit._declarations import suite_declarations
from scratchworld_dist.kinds.audit._panel import variant_panel
from scratchworld_dist.kinds.audit._plan import DEFAULT_AGENT, AuditBody, AuditSweep, audit_jobs, evaluated_under
from scratchworld_dist.kinds.audit._rows import AuditRow, audit_row
from scratchworld_dist.kinds.base import Kind
from scratchworld_dist.kinds.tasks import episode_settings, selected_tasks
from scratchworld_dist.reports import ReportFormat
from scratchworld_dist.sweep import JobSpec, Notice, RunPlan, SuiteInfo, SweepConfig, suite_hash
from scratchworld_dist.viewer import AttemptPanel
from workers.contract import AgentRef, AgentUnavailableError, HarnessFingerprint, JobResult
from workers.kinds.audit import AuditSpec


class AuditKind(Kind):
    """Task x variant: each variant of a golden evaluated once, in a clean evaluation editor."""

    name = "audit"
    rank = 30
    title = "grader audit"
    needs_browser = True
    tables: ClassVar[Mapping[str, type[BaseModel]]] = MappingProxyType({"audits": AuditRow})
    config_section: type[BaseModel] | None = AuditSweep
    regrade_refusal: str | None = "an audit run evaluates variants of goldens: run the audit again instead"

    def check_agent(self, agent: AgentRef) -> None:
        if agent != DEFAULT_AGENT:
            raise AgentUnavailableError("the grader audit runs no agent: leave agent out")

    def check_sweep(self, config: SweepConfig) -> None:
        episodes = episode_settings(config)
        if config.models or episodes.memory is not None or episodes.synthetic is not None:
            raise ValueError("the grader audit calls no model: leave models, memory and synthetic out")

    def needs_model(self, config: SweepConfig) -> bool:
        return False

    def plan(self, config: SweepConfig, harness: HarnessFingerprint, notice: Notice) -> RunPlan:
        """The selected tasks' goldens and every variant the ``audit`` section asks for, one job each, evaluated
        under ``evaluated_under(config)``."""
        suite, contents = selected_tasks(evaluated_under(config), None)
        settings = config.section(self.name, AuditSweep)
        declarations = suite_declarations(suite, settings.explanations)
        jobs = list(audit_jobs(contents, settings, DEFAULT_AGENT, harness.digest, config.project_limits, declarations))
        info = SuiteInfo(
            name=suite.name, kind=suite.kind, root=str(suite.root), hash=suite_hash(contents), tasks=len(contents)
        )
        return RunPlan(config=config, harness=harness, suite=info, contents=contents, jobs=jobs)

    def worker_job(self, job: JobSpec, attempt: int, timeout_s: float) -> AuditSpec:
        body = job.body
        if not isinstance(body, AuditBody):
            raise ValueError(f"job {job.job_id} is not an audit job")
        return AuditSpec(
            **job.worker_header(attempt, timeout_s),
            variant=body.variant,
            project_json=body.project_json,
            exploration=body.exploration,
            stop_at_first_failure=body.stop_at_first_failure,
        )

    def own_rows(self, job: JobSpec, result: JobResult, artifact_dir: str | None) -> dict[str, list[BaseModel]]:
        return {"audits": [audit_row(job, result)]}

    def report_model(self) -> type[BaseModel]:
        from scratchworld_dist.kinds.audit._report import AuditReport

        return AuditReport

    def report_data(self, run_dirs: Sequence[Path], *, force: bool) -> BaseModel:
        from scratchworld_dist.kinds.audit._report import build_audit_report

        return build_audit_report(run_dirs, force=force)

    def render_report(self, data: BaseModel, fmt: ReportFormat) -> str:
        from scratchworld_dist.kinds.audit._report import AuditReport
        from scratchworld_dist.kinds.audit._report_blocks import render_audit

        assert isinstance(data, AuditReport)
        return render_audit(data, fmt)

    def report_html(self, run_dir: Path) -> tuple[str, list[str]]:
        """The report on the run's page, its findings linking to their job pages next to it."""
        from scratchworld_dist.kinds.audit._report import build_audit_report, job_page
        from scratchworld_dist.kinds.audit._report_blocks import render_audit

        report = build_audit_report([run_dir], force=False)
        return render_audit(report, "html", link=lambda finding: job_page(finding.job_id)), report.warnings

    def attempt_panel(self, rows: Mapping[str, Sequence[BaseModel]], root: str, run_dir: Path) -> AttemptPanel | None:
        return variant_panel(rows, run_dir)


AUDIT = AuditKind()
"""The registered kind (entry point ``audit``)."""
