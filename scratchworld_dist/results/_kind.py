"""What the results ask of a benchmark kind: the rows of its own tables for one attempt, what its run stores once
for many rows, and whether a run directory written before rows named their benchmark holds its jobs."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Protocol

from pydantic import BaseModel

from scratchworld_dist.kinds import KindTraits
from scratchworld_dist.sweep import ItemContent, JobSpec
from workers.contract import JobResult


class SharedFiles(Protocol):
    """Where a run keeps files many of its rows refer to (``RunStore``)."""

    def write_shared_image(self, path: str, data: bytes) -> None: ...


class KindRows(KindTraits):
    """The results facet of a kind. Defaults: no table of its own, nothing shared, no claim on older runs."""

    regrade_refusal: str | None = "its runs store no episodes' final projects: nothing to regrade"
    """Why its runs cannot be regraded (None: they store projects a regrade evaluates again)."""

    def own_rows(self, job: JobSpec, result: JobResult, artifact_dir: str | None) -> dict[str, list[BaseModel]]:
        """The rows of this kind's own ``tables`` for one attempt (``artifact_dir``: where its files went)."""
        return {}

    def store_shared(self, files: SharedFiles, contents: Sequence[ItemContent]) -> None:
        """Store once per run what many of its jobs' rows refer to (a perception item's screenshot)."""
        return None

    def holds(self, run_dir: Path) -> bool:
        """Whether a run directory written before rows named their benchmark holds this kind's jobs."""
        return False
