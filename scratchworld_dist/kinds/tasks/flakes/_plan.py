"""Which perturbed evaluations the flake finder runs: one axis varied at a time, from a baseline.

Varying one condition per run makes a flipped verdict name its cause. Every value is drawn from
the settings' seed, so a flake run can be repeated exactly (apart from the wall clock and the load).
"""

from __future__ import annotations

import random
from typing import Literal, get_args

from pydantic import BaseModel, ConfigDict, Field

from workers.contract import (
    VM_FRAME_MS,
    EvaluationClock,
    EvaluationPerturbation,
    EvaluationRender,
    EvaluationTiming,
    TimerLateness,
    frames_per_second,
)

Axis = Literal["seed", "phase", "mouse", "lateness", "clock", "render", "load"]
"""A perturbation: the page's random seed, the frame phase at script start, the mouse's start
position, timer lateness (virtual clock), the other clock, the other render mode, CPU load."""

AXES: tuple[Axis, ...] = get_args(Axis)

DEFAULT_LATENESS_MS: tuple[float, ...] = (0, 4, 8, 15, 25)
"""Lateness levels per repeating timer: 30.3, 27.0, 24.4, 20.8 and 17.2 VM frames per second."""


class FlakeSettings(BaseModel):
    """What a flake run varies and how often; recorded with its report."""

    model_config = ConfigDict(frozen=True)

    runs: int = Field(default=3, ge=1, le=50)
    """Runs per axis with drawn values (seed, phase, mouse, clock, load); render has one other value."""
    axes: tuple[Axis, ...] = AXES
    lateness_ms: tuple[float, ...] = DEFAULT_LATENESS_MS
    seed: int = Field(default=0, ge=0)
    """Seed of every drawn value (random seeds, mouse positions)."""
    load_processes: int = Field(default=2, ge=1, le=64)
    """Busy processes burning CPU during the ``load`` runs."""


class Variant(BaseModel):
    """The conditions of one evaluation of a flake run."""

    model_config = ConfigDict(frozen=True)

    axis: Axis | Literal["baseline"]
    label: str
    """The varied value, for people (e.g. ``phase 8 ms``, ``lateness 15 ms (20.8 fps)``)."""
    clock: EvaluationClock
    render: EvaluationRender
    perturbation: EvaluationPerturbation
    timing: EvaluationTiming = "ideal"
    """Frame timing in virtual time (always ``ideal`` on the real clock, which has its own)."""
    cpu_load: int = 0
    """Busy processes running meanwhile."""


def plan_variants(
    settings: FlakeSettings, clock: EvaluationClock, render: EvaluationRender, timing: EvaluationTiming = "ideal"
) -> list[Variant]:
    """The baseline (the task's own clock, render and virtual frame timing, phase 0, no lateness) and the
    varied runs, in order. The lateness axis runs its levels on ideal timing, then the calibrated model once,
    so that the report shows which tests depend on the frame timing at all."""
    draw = random.Random(settings.seed)
    base = EvaluationPerturbation(random_seed=draw.randrange(2**32))

    def variant(axis: Axis | Literal["baseline"], label: str, **changes: object) -> Variant:
        perturbation = base.model_copy(update=changes.pop("perturbation", {}))
        fields: dict[str, object] = {"clock": clock, "render": render, "timing": timing, **changes}
        if fields["clock"] == "real":
            fields["timing"] = "ideal"
        return Variant(axis=axis, label=label, perturbation=perturbation, **fields)  # type: ignore[arg-type]

    variants = [variant("baseline", "baseline")]

    def add(axis: Axis, label: str, **changes: object) -> None:
        variants.append(variant(axis, label, **changes))

    for axis in settings.axes:
        for index in range(settings.runs):
            if axis == "seed":
                seed = draw.randrange(2**32)
                add(axis, f"seed {seed}", perturbation={"random_seed": seed})
            elif axis == "phase":  # spread over the frame interval, the baseline being 0
                phase = round((index + 1) * VM_FRAME_MS / (settings.runs + 1), 1)
                add(axis, f"phase {phase:g} ms", clock="virtual", perturbation={"phase_ms": phase})
            elif axis == "mouse":
                mouse = (float(draw.randint(-240, 240)), float(draw.randint(-180, 180)))
                add(axis, f"mouse ({mouse[0]:g}, {mouse[1]:g})", perturbation={"mouse": mouse})
            elif axis == "clock":
                other: EvaluationClock = "real" if clock == "virtual" else "virtual"
                add(axis, f"clock {other} #{index + 1}", clock=other)
            elif axis == "load":
                add(axis, f"load {settings.load_processes} procs #{index + 1}", cpu_load=settings.load_processes)
        if axis == "render":
            other_render: EvaluationRender = "every_frame" if render == "on_demand" else "on_demand"
            add(axis, f"render {other_render}", render=other_render)
        elif axis == "lateness":
            for ms in settings.lateness_ms:
                lateness = TimerLateness(ms=ms)
                label = f"lateness {ms:g} ms ({frames_per_second(ms):.1f} fps)"
                add(axis, label, clock="virtual", timing="ideal", perturbation={"lateness": lateness})
            add(axis, "calibrated frame timing", clock="virtual", timing="calibrated")
    return variants
