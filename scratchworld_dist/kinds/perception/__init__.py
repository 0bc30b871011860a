"""The perception QA kind (``benchmark: perception``): planning, rows and report of one answer per job.

Its names are imported on first use (``workers.lazy_exports``): the command line imports its command modules,
inside this package, without loading the kind."""

import typing

import workers

if typing.TYPE_CHECKING:
    from scratchworld_dist.kinds.perception._kind import PERCEPTION, PerceptionKind
    from scratchworld_dist.kinds.perception._plan import (
        PerceptionBody,
        PerceptionContent,
        PerceptionItemInfo,
        plan_perception_jobs,
        read_perception_item,
        select_perception_items,
    )
    from scratchworld_dist.kinds.perception._rows import PerceptionRow

__getattr__ = workers.lazy_exports(
    __name__,
    {
        "._kind": (
            "PERCEPTION",
            "PerceptionKind",
        ),
        "._plan": (
            "PerceptionBody",
            "PerceptionContent",
            "PerceptionItemInfo",
            "plan_perception_jobs",
            "read_perception_item",
            "select_perception_items",
        ),
        "._rows": ("PerceptionRow",),
    },
)

__all__ = [
    "PERCEPTION",
    "PerceptionBody",
    "PerceptionContent",
    "PerceptionItemInfo",
    "PerceptionKind",
    "PerceptionRow",
    "plan_perception_jobs",
    "read_perception_item",
    "select_perception_items",
]
