"""The grader audit kind (``benchmark: audit``): mutants and refactorings of goldens, judged by the tasks' tests."""

from scratchworld_dist.kinds.audit._kind import AUDIT, AuditKind
from scratchworld_dist.kinds.audit._plan import AuditBody, AuditSweep, audit_jobs, task_variants
from scratchworld_dist.kinds.audit._report import AuditReport, build_audit_report
from scratchworld_dist.kinds.audit._report_blocks import render_audit
from scratchworld_dist.kinds.audit._rows import AuditRow

__all__ = [
    "AUDIT",
    "AuditBody",
    "AuditKind",
    "AuditReport",
    "AuditRow",
    "AuditSweep",
    "audit_jobs",
    "build_audit_report",
    "render_audit",
    "task_variants",
]
