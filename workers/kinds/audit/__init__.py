"""The ``audit`` kind inside a worker: a variant of a task's golden project evaluated by the task's tests, no
agent; a variant the tests misjudge is compared with the golden by behaviour (the tests' own run and the task's
exploration), and the golden's job checks whether the tests judge anything. Its contract with the driver:
``AuditSpec`` (the job, with the task's ``ExplorationPlan``), ``AuditObservation`` and ``GraderCheck`` (what the
runs showed)."""

from workers.kinds.audit._contract import (
    AuditObservation,
    AuditSpec,
    GraderCheck,
    Observed,
    ShownBy,
    Vacuity,
    VariantKind,
)
from workers.kinds.audit._exploration import (
    ANSWER_DOMAINS,
    AnswerDomain,
    ExplorationEpisode,
    ExplorationPlan,
    Stimulus,
    StimulusKind,
    in_domain,
)
from workers.kinds.audit._kind import AUDIT, AuditKind

__all__ = [
    "ANSWER_DOMAINS",
    "AUDIT",
    "AnswerDomain",
    "AuditKind",
    "AuditObservation",
    "AuditSpec",
    "ExplorationEpisode",
    "ExplorationPlan",
    "GraderCheck",
    "Observed",
    "ShownBy",
    "Stimulus",
    "StimulusKind",
    "Vacuity",
    "VariantKind",
    "in_domain",
]
