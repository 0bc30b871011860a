"""Job kinds: the benchmarks a sweep can run (task episodes, single-step drag, perception QA, a plugin's).

Each kind is one folder here with everything the driver does differently for it; the core reaches a kind
only through ``job_kind(name)``.
"""

from scratchworld_dist.kinds._protocol import AttemptPanel, DiagnosisPart, JobKind, Notice, section_key
from scratchworld_dist.kinds._registry import (
    DEFAULT_KIND,
    ENTRY_POINT_GROUP,
    UnknownKindError,
    job_kind,
    job_kinds,
    kind_names,
    kind_of_run,
)

__all__ = [
    "DEFAULT_KIND",
    "ENTRY_POINT_GROUP",
    "AttemptPanel",
    "DiagnosisPart",
    "JobKind",
    "Notice",
    "UnknownKindError",
    "job_kind",
    "job_kinds",
    "kind_names",
    "kind_of_run",
    "section_key",
]
