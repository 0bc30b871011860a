"""The visual perception QA benchmark's items: upstream's 200 and our own format, behind one loader; and making
and validating a suite in a real editor (``make_perception_suite``, ``validate_perception_suite``), which need
the browser stack and so are imported on first use."""

import typing

import workers
from scratchworld_dist.kinds.perception.items._detect import PERCEPTION_LOADERS, load_perception_suite
from scratchworld_dist.kinds.perception.items._item import (
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
from scratchworld_dist.kinds.perception.items._native import (
    NativePerceptionLoader,
    read_screenshot,
    write_perception_suite,
)
from scratchworld_dist.kinds.perception.items._suite import PerceptionSuite
from scratchworld_dist.kinds.perception.items._upstream import UpstreamPerceptionLoader

if typing.TYPE_CHECKING:
    from scratchworld_dist.kinds.perception.items._make import make_perception_suite
    from scratchworld_dist.kinds.perception.items._validate import ViewCheck, refuse_upstream, validate_perception_suite

__getattr__ = workers.lazy_exports(
    __name__,
    {
        "._make": ("make_perception_suite",),
        "._validate": ("ViewCheck", "refuse_upstream", "validate_perception_suite"),
    },
)

__all__ = [
    "PERCEPTION_LOADERS",
    "BlockReference",
    "ConnectionFact",
    "ExistenceFact",
    "Fact",
    "FieldFact",
    "NativePerceptionLoader",
    "PerceptionItem",
    "PerceptionSuite",
    "PerceptionView",
    "Position",
    "UpstreamItemInfo",
    "UpstreamPerceptionLoader",
    "ViewCheck",
    "load_perception_suite",
    "make_perception_suite",
    "read_screenshot",
    "refuse_upstream",
    "validate_perception_suite",
    "write_perception_suite",
]
