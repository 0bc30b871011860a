"""Perturbations of an evaluation that must not change a verdict, as recorded data (``scratchworld flakes``).

A stable test gives the same verdict whatever the page's random numbers, the phase at which the
script meets the VM's frame loop, where the mouse starts, or how late timers fire; the flake finder
varies these on purpose, and every value used is recorded with the verdict it gave.
"""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, field_validator

LatenessModel = Literal["fixed", "uniform"]
"""How late a repeating timer fires (``scratch-gui/clock.js``): ``fixed``, every firing ``ms`` late;
``uniform``, drawn from [0, 2 ms) by a generator seeded with ``seed`` (mean ``ms``)."""

VM_FRAME_MS = 33
"""The VM's frame interval on the page clock (``1000 / 30`` ms, truncated to whole ms by the timer rules)."""

MAX_SEED = 2**32 - 1


def frames_per_second(lateness_ms: float) -> float:
    """The VM's frame rate when every frame comes ``lateness_ms`` late."""
    return 1000 / (VM_FRAME_MS + lateness_ms)


class TimerLateness(BaseModel):
    """Lateness of every repeating timer under the virtual clock; 0 ms is the exact timing of an unperturbed run."""

    model_config = ConfigDict(frozen=True)

    model: LatenessModel = "fixed"
    ms: float = Field(default=0, ge=0, le=1000)
    """Per firing (``fixed``) or on average (``uniform``)."""
    seed: int = Field(default=0, ge=0, le=MAX_SEED)
    """Seed of the lateness draws (``uniform``)."""


class EvaluationPerturbation(BaseModel):
    """The page conditions of one perturbed evaluation; every value changes nothing for a stable test."""

    model_config = ConfigDict(frozen=True)

    random_seed: int = Field(ge=0, le=MAX_SEED)
    """Seed of the page's ``Math.random`` for the whole script run (the VM's "pick random" included)."""

    phase_ms: float = Field(default=0, ge=0, lt=1000)
    """Time from the script's start to the VM's next frame (0: the script starts right at a frame);
    virtual clock only (on the real clock the phase is whatever the wall clock gives)."""

    mouse: tuple[float, float] | None = None
    """Where a real mouse event puts the mouse before the project loads, in stage coordinates
    (x in -240..240, y in -180..180); None: where the profile puts it (or nowhere)."""

    lateness: TimerLateness | None = None
    """Timer lateness under the virtual clock; None: none."""

    @field_validator("mouse")
    @classmethod
    def _on_stage(cls, mouse: tuple[float, float] | None) -> tuple[float, float] | None:
        if mouse is not None and not (abs(mouse[0]) <= 240 and abs(mouse[1]) <= 180):
            raise ValueError(f"the mouse must start on the stage (x in -240..240, y in -180..180), got {mouse}")
        return mouse
