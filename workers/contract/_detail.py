"""The part of a job's result that only its kind has (a drag's points and distances, a perception answer's
scores): one field of ``JobResult``, told apart by ``kind``."""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict


class JobDetail(BaseModel):
    """A kind's own result; each kind's detail adds its fields (a plugin kind's too)."""

    model_config = ConfigDict(frozen=True)

    kind: str
    """The job kind that made it (``drag``, ``perception`` or a plugin's)."""
