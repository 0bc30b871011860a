"""Choosing a perception-suite loader from what a folder looks like."""

from __future__ import annotations

from pathlib import Path
from typing import Protocol

from scratchworld_dist._errors import SuiteError
from scratchworld_dist.perception._native import SUITE_FILE, NativePerceptionLoader
from scratchworld_dist.perception._suite import PerceptionSuite
from scratchworld_dist.perception._upstream import BENCHMARK_DIR, UpstreamPerceptionLoader


class PerceptionSuiteLoader(Protocol):
    kind: str

    @staticmethod
    def handles(root: Path) -> bool: ...

    def load(self, root: Path) -> PerceptionSuite: ...


PERCEPTION_LOADERS: tuple[PerceptionSuiteLoader, ...] = (NativePerceptionLoader(), UpstreamPerceptionLoader())


def load_perception_suite(path: str | Path) -> PerceptionSuite:
    """Load the perception suite at ``path`` (ours, a clone, or a clone's ``visual_perception_benchmark``).

    Raises ``SuiteError`` only when there is no suite to speak of (no folder, no recognisable layout, an
    unreadable manifest); a bad item is left out and listed in ``PerceptionSuite.problems``.
    """
    root = Path(path).expanduser().absolute()
    if not root.is_dir():
        raise SuiteError("not a directory" if root.exists() else "no such directory", root)
    candidates = [root, root.parent] if root.name == BENCHMARK_DIR.name else [root]
    for candidate in candidates:
        for loader in PERCEPTION_LOADERS:
            if loader.handles(candidate):
                return loader.load(candidate)
    raise SuiteError(
        f"not a perception suite: expected {SUITE_FILE} (a scratchworld_dist perception suite) or "
        f"{BENCHMARK_DIR}/ (a clone of the upstream ScratchWorld repository)",
        root,
    )
