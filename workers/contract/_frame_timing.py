"""How the VM's frames are timed in virtual time: exactly on time, or as late as Chromium runs them.

Upstream goldens are sensitive to the frame rate on both sides (issue 20), and real frames may come
late, heavy ones later. ``calibrated`` makes each virtual frame late by a linear function of the work
the VM did in it, with coefficients fitted on real runs (``benchmarks/frame_lateness.py``) and stored
in ``frame_timing.json`` next to this module. Measured here on an idle machine, Chromium's frame loop
keeps its 33 ms grid whatever the work, so every coefficient fits to 0 (docs/evaluation.md, "Frame timing").
"""

from __future__ import annotations

from functools import cache
from pathlib import Path
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field

EvaluationTiming = Literal["ideal", "calibrated"]
"""Frame timing under the virtual clock: ``ideal``, every frame exactly on time (33 ms apart);
``calibrated``, each frame late by the fitted ``FrameLateness`` of the work it did."""

RecordedTiming = Literal["ideal", "calibrated", "real"]
"""The frame timing a verdict was made under: one of the virtual models, or the real clock's own."""

CALIBRATION_FILE = Path(__file__).with_name("frame_timing.json")


class FrameLateness(BaseModel):
    """A frame's lateness in ms: ``fixed_ms + per_block_ms * blocks + per_redraw_ms * redraw`` (at least 0),
    where ``blocks`` counts the block functions the VM called in the frame and ``redraw`` is 1 when a
    block asked for a redraw."""

    model_config = ConfigDict(frozen=True)

    fixed_ms: float = Field(ge=0, le=1000)
    per_block_ms: float = Field(ge=0, le=1000)
    per_redraw_ms: float = Field(ge=0, le=1000)
    """No coefficient is negative: work never makes a frame come early (the fit is non-negative)."""

    def bridge_args(self) -> dict[str, float]:
        """The page's view (``scratch-gui/bridge.js``, ``frameTiming``)."""
        return {"fixedMs": self.fixed_ms, "perBlockMs": self.per_block_ms, "perRedrawMs": self.per_redraw_ms}


class FrameTimingCalibration(BaseModel):
    """The fitted model and where it was measured (the calibration file)."""

    model_config = ConfigDict(frozen=True)

    lateness: FrameLateness
    measured_on: str
    """Date of the measurement (ISO)."""
    machine: dict[str, str | int | float]
    """CPU, cores, load average, browser: what the coefficients hold for."""
    method: str
    """How the coefficients were fitted."""
    frames: int = Field(ge=0)
    """Frames the fit used."""
    projects: list[dict[str, str | float]] = Field(default_factory=list)
    """Per project: real, virtual-ideal and virtual-calibrated frames per second."""


@cache
def calibrated_frame_lateness() -> FrameLateness:
    """The repository's calibrated frame lateness (re-measure with ``benchmarks/frame_lateness.py``)."""
    return FrameTimingCalibration.model_validate_json(CALIBRATION_FILE.read_text(encoding="utf-8")).lateness
