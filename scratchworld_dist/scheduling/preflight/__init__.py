"""Preflight: every model a sweep calls is checked (its key and base URL set, and by default one smallest call
made) before any editor opens, so a wrong key stops the run in seconds, naming the model."""

from scratchworld_dist.scheduling.preflight._check import (
    PreflightError,
    broken_line,
    refuse_broken,
    run_preflight,
    settle,
)
from scratchworld_dist.scheduling.preflight._models import ModelCalls

__all__ = ["ModelCalls", "PreflightError", "broken_line", "refuse_broken", "run_preflight", "settle"]
