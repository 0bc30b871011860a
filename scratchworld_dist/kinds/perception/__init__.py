"""The perception QA kind (``benchmark: perception``): planning, rows and report of one answer per job."""

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
