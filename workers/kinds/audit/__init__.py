"""The ``audit`` kind inside a worker: a variant of a task's golden project evaluated by the task's tests, no
agent; a variant the tests misjudge is traced beside the golden to tell whether it behaves the same."""

from workers.kinds.audit._kind import AUDIT, AuditKind

__all__ = ["AUDIT", "AuditKind"]
