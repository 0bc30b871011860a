"""The config's ``loggers:`` section: experiment trackers a run reports to (MLflow, Weights & Biases), all optional.

None of it changes a job (the config hash leaves it out), so a run may gain or drop a tracker when it resumes.
Each tracker's package is an optional extra (``pip install scratchworld-dist[mlflow]``, ``[wandb]``), imported only
when its entry is configured.
"""

from __future__ import annotations

from pathlib import Path
from typing import Literal
from urllib.parse import urlsplit

from pydantic import BaseModel, ConfigDict, Field, field_validator


class MLflowLogger(BaseModel):
    """An MLflow tracking store: a server (``http://host:5000``), a ``file:`` folder or a ``sqlite:`` database."""

    model_config = ConfigDict(extra="forbid")

    tracking_uri: str | None = None
    """Where runs are kept (default: ``MLFLOW_TRACKING_URI``, else MLflow's own default). Never with credentials
    in it (the config is recorded in the run's manifest): MLflow reads them from its own variables."""

    @field_validator("tracking_uri")
    @classmethod
    def _no_credentials(cls, uri: str | None) -> str | None:
        if uri is not None and "@" in urlsplit(uri).netloc:
            raise ValueError(
                "a tracking URI with credentials would be recorded with the run: give them in "
                "MLFLOW_TRACKING_USERNAME and MLFLOW_TRACKING_PASSWORD (or MLFLOW_TRACKING_TOKEN) instead"
            )
        return uri

    experiment: str | None = None
    """The experiment the run is logged under (default: the sweep's name)."""

    run_name: str | None = None
    """The tracker run's display name (default: the sweep's name)."""


class WandbLogger(BaseModel):
    """A Weights & Biases project; ``mode: offline`` writes the run to ``dir`` for a later ``wandb sync``."""

    model_config = ConfigDict(extra="forbid")

    project: str | None = None
    """The project (default: the sweep's name)."""

    entity: str | None = None
    """The team or user (default: the API key's)."""

    mode: Literal["online", "offline"] | None = None
    """``offline``: nothing leaves the machine (default: ``WANDB_MODE``, else online)."""

    dir: Path | None = None
    """Where W&B writes its run files (default: its own, ``./wandb``); relative to the config's folder."""


class Loggers(BaseModel):
    """Experiment trackers the run reports to: its parameters at the start, its metrics as jobs finish (from a
    background thread, never holding up the scheduler), its report and leaderboard at the end."""

    model_config = ConfigDict(extra="forbid")

    mlflow: MLflowLogger | None = None
    wandb: WandbLogger | None = None

    every_results: int = Field(default=10, ge=1)
    """Metrics are sent after this many finished attempts..."""

    every_s: float = Field(default=30.0, gt=0)
    """...or this many seconds after the last sending, whichever comes first (and once at the end)."""

    finish_timeout_s: float = Field(default=60.0, gt=0)
    """How long the run waits at its end for a tracker to take its last metrics and artifacts; a tracker still
    busy then is left behind (said once), the run's results are unaffected."""

    def configured(self) -> dict[str, BaseModel]:
        """The configured trackers by name."""
        return {name: entry for name in ("mlflow", "wandb") if (entry := getattr(self, name)) is not None}
