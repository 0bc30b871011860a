"""The trackers by their ``loggers:`` key; each one's module (and package) is imported only when it is configured."""

from __future__ import annotations

import importlib
import importlib.util

from pydantic import BaseModel

from scratchworld_dist._errors import ConfigError
from scratchworld_dist.sweep._loggers import Loggers
from scratchworld_dist.trackers._tracker import Tracker

TRACKERS = {
    "mlflow": ("scratchworld_dist.trackers._mlflow", "MLflowTracker", "mlflow", "mlflow"),
    "wandb": ("scratchworld_dist.trackers._wandb", "WandbTracker", "wandb", "wandb"),
}
"""Key: (module, class, the package it imports, the extra that installs it)."""


def configured_trackers(loggers: Loggers) -> list[Tracker]:
    """The trackers ``loggers`` configures; ``ConfigError`` names the extra to install for one whose package is
    missing (before any job runs: a run that asked for a tracker should not find out at its end)."""
    found: list[Tracker] = []
    for name, settings in loggers.configured().items():
        module, cls, package, extra = TRACKERS[name]
        if importlib.util.find_spec(package) is None:
            raise ConfigError(
                f"loggers.{name}: the {package} package is not installed: pip install 'scratchworld-dist[{extra}]'"
            )
        found.append(_tracker(module, cls, settings))
    return found


def _tracker(module: str, cls: str, settings: BaseModel) -> Tracker:
    tracker: Tracker = getattr(importlib.import_module(module), cls)(settings)
    return tracker
