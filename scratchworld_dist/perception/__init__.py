"""The visual perception QA benchmark's items: upstream's 200 and our own format, behind one loader."""

from scratchworld_dist.perception._detect import PERCEPTION_LOADERS, load_perception_suite
from scratchworld_dist.perception._item import (
    BlockReference,
    ConnectionFact,
    ExistenceFact,
    Fact,
    FieldFact,
    PerceptionItem,
    PerceptionView,
    Position,
    UpstreamItemInfo,
)
from scratchworld_dist.perception._native import NativePerceptionLoader, read_screenshot, write_perception_suite
from scratchworld_dist.perception._suite import PerceptionProblem, PerceptionSuite, PerceptionSuiteKind
from scratchworld_dist.perception._upstream import UpstreamPerceptionLoader

__all__ = [
    "PERCEPTION_LOADERS",
    "BlockReference",
    "ConnectionFact",
    "ExistenceFact",
    "Fact",
    "FieldFact",
    "NativePerceptionLoader",
    "PerceptionItem",
    "PerceptionProblem",
    "PerceptionSuite",
    "PerceptionSuiteKind",
    "PerceptionView",
    "Position",
    "UpstreamItemInfo",
    "UpstreamPerceptionLoader",
    "load_perception_suite",
    "read_screenshot",
    "write_perception_suite",
]
