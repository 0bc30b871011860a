"""Benchmark kinds: task episodes, single-step drag, perception QA, grader audits, and any a plugin registers.

Each kind is one folder here with everything the driver does for it, built on ``scratchworld_dist.kinds.base.Kind``
(which joins the facets each layer defines: planning in ``sweep``, rows in ``results``, reports in ``reports``,
panels in ``viewer``). This package's face is the registry every layer finds kinds through; it imports no kind.
"""

from scratchworld_dist.kinds._registry import (
    DEFAULT_KIND,
    ENTRY_POINT_GROUP,
    KindTraits,
    UnknownKindError,
    job_kind,
    job_kinds,
    kind_names,
)

__all__ = [
    "DEFAULT_KIND",
    "ENTRY_POINT_GROUP",
    "KindTraits",
    "UnknownKindError",
    "job_kind",
    "job_kinds",
    "kind_names",
]
