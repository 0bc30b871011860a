"""The grader audit kind (``benchmark: audit``): mutants and refactorings of goldens, judged by the tasks' tests.

Its names are imported on first use (``workers.lazy_exports``): the command line imports its command modules,
inside this package, without loading the kind."""

import typing

import workers

if typing.TYPE_CHECKING:
    from scratchworld_dist.kinds.audit._kind import AUDIT, AuditKind
    from scratchworld_dist.kinds.audit._plan import AuditBody, AuditSweep, audit_jobs, task_variants
    from scratchworld_dist.kinds.audit._report import AuditReport, build_audit_report
    from scratchworld_dist.kinds.audit._report_blocks import render_audit
    from scratchworld_dist.kinds.audit._rows import AuditRow

__getattr__ = workers.lazy_exports(
    __name__,
    {
        "._kind": (
            "AUDIT",
            "AuditKind",
        ),
        "._plan": (
            "AuditBody",
            "AuditSweep",
            "audit_jobs",
            "task_variants",
        ),
        "._report": (
            "AuditReport",
            "build_audit_report",
        ),
        "._report_blocks": ("render_audit",),
        "._rows": ("AuditRow",),
    },
)

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
