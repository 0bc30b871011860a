"""The ``audit`` kind inside a worker: a variant of a task's golden project evaluated by the task's tests, no
agent; a variant the tests misjudge is traced beside the golden to tell whether it behaves the same. Its contract
with the driver: ``AuditSpec`` (the job) and ``AuditObservation`` (what the traces showed)."""

from workers.kinds.audit._contract import AuditObservation, AuditSpec, VariantKind
from workers.kinds.audit._kind import AUDIT, AuditKind

__all__ = ["AUDIT", "AuditKind", "AuditObservation", "AuditSpec", "VariantKind"]
