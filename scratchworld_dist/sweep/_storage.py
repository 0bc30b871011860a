"""Where a sweep's run directory lives when ``output`` is a URL (``s3://bucket/prefix``, any fsspec URL): the
local mirror the driver writes first, how long its lease on the bucket lasts, how long it waits for uploads at
the end. None of it changes a job (the config hash leaves it out)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from pydantic import BaseModel, ConfigDict, Field


class StorageSettings(BaseModel):
    """The ``storage:`` section (docs/object-storage.md)."""

    model_config = ConfigDict(extra="forbid")

    cache_dir: Path | None = None
    """Where local mirrors of remote runs live (default ``~/.cache/scratchworld/runs``; each run in
    ``<protocol>/<bucket>/<prefix>`` under it)."""

    lease_ttl_s: float = Field(default=120.0, gt=0)
    """How long the run's lease outlives a driver that stopped renewing it (renewed every third of it)."""

    drain_timeout_s: float = Field(default=120.0, ge=0)
    """How long a finished sweep waits for pending uploads before it stops, saying what is still pending."""


def checked_output(value: Any) -> Any:
    """``output`` as given: a URL (checked: no credentials in it) stays text, anything else is a path."""
    if isinstance(value, str) and "://" in value:
        from scratchworld_dist.results.remote._location import parse_location  # not at import: results imports sweep

        try:
            return parse_location(value).url
        except Exception as exc:
            raise ValueError(str(exc)) from None
    return Path(value) if isinstance(value, str) else value
