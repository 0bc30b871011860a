"""What the run asks of an experiment tracker (``Tracker``), and what it hands one when it starts (``RunInfo``).

A tracker is called from its own thread only (``TrackerFeed``), one call at a time, so it needs no locking; whatever
it raises is caught there. Its package is imported in ``start``, never when this module is.
"""

from __future__ import annotations

import re
from typing import Protocol

from pydantic import BaseModel, Field


class RunInfo(BaseModel):
    """The run as a tracker records it."""

    name: str
    """The sweep's name (the default experiment, project and run name)."""

    key: str
    """The run's own key (``TrackerRuns.key``): the same in every session of the run directory."""

    params: dict[str, str]
    """What the run is: models with their settings, modes, suite and its hash, harness, agent, seeds."""

    tags: dict[str, str] = Field(default_factory=dict)
    """The run's labels (they may grow when it resumes, so they are tags, not parameters)."""

    run_ids: dict[str, str] = Field(default_factory=dict)
    """Each tracker's run id as an earlier session recorded it, by tracker name (none: a new run, or one to find
    by ``key``)."""


class Tracker(Protocol):
    """An experiment tracker's side of a run."""

    name: str

    def start(self, run: RunInfo) -> str:
        """Open (or continue) the run, record its parameters; return the tracker's run id."""
        ...

    def log_metrics(self, metrics: dict[str, float], step: int) -> None:
        """Record the metrics as of ``step`` (decided jobs so far)."""
        ...

    def log_artifacts(self, files: dict[str, bytes]) -> None:
        """Attach these files (name: content) to the run."""
        ...

    def finish(self, status: str) -> None:
        """Close the run: ``finished``, ``interrupted`` or ``failed`` (as the sweep ended)."""
        ...


_USERINFO = re.compile(r"(?<=://)[^/@\s]+@")


def redacted(text: str) -> str:
    """``text`` with the credentials of any URL in it (``https://user:token@host``) left out."""
    return _USERINFO.sub("***@", text)
