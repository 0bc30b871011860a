"""Choosing a perception-suite loader from what a folder looks like."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from scratchworld_dist.kinds.perception.items._native import SUITE_FILE, NativePerceptionLoader
from scratchworld_dist.kinds.perception.items._suite import PerceptionSuite
from scratchworld_dist.kinds.perception.items._upstream import BENCHMARK_DIR, UpstreamPerceptionLoader
from scratchworld_dist.suites import SuiteLoader, load_with

PERCEPTION_LOADERS: tuple[SuiteLoader[PerceptionSuite], ...] = (NativePerceptionLoader(), UpstreamPerceptionLoader())

NOT_A_PERCEPTION_SUITE = (
    f"not a perception suite: expected {SUITE_FILE} (a scratchworld_dist perception suite) or "
    f"{BENCHMARK_DIR}/ (a clone of the upstream ScratchWorld repository)"
)


def _clone_above(root: Path) -> Sequence[Path]:
    """A clone's ``visual_perception_benchmark/`` folder stands for the clone."""
    return (root.parent,) if root.name == BENCHMARK_DIR.name else ()


def load_perception_suite(path: str | Path) -> PerceptionSuite:
    """Load the perception suite at ``path`` (ours, a clone, or a clone's ``visual_perception_benchmark``).

    Raises ``SuiteError`` only when there is no suite to speak of (no folder, no recognisable layout, an
    unreadable manifest); a bad item is left out and listed in ``PerceptionSuite.problems``.
    """
    return load_with(path, PERCEPTION_LOADERS, NOT_A_PERCEPTION_SUITE, _clone_above)
