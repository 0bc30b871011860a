"""The perception QA kind (``benchmark: perception``): planning, rows and report of one answer per job."""

from scratchworld_dist.kinds.perception._kind import PERCEPTION, PerceptionJobKind
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
    "PerceptionJobKind",
    "PerceptionRow",
    "plan_perception_jobs",
    "read_perception_item",
    "select_perception_items",
]
