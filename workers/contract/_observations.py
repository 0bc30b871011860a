"""What an agent sees: the observation of each mode, as plain data a plugin can import without a browser, and
how primitive observations are made (``ObservationSettings``, part of a primitive job's identity).

Composite mode shows the project as text; primitive mode a screenshot with an indexed element
list (the DOM fused with OCR). The environments that build them live in ``workers.composite``
and ``workers.primitive``.
"""

from __future__ import annotations

import hashlib
from pathlib import Path
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator


class TargetName(BaseModel):
    """A sprite or the stage, as composite observations list them."""

    model_config = ConfigDict(frozen=True, populate_by_name=True)

    name: str
    is_stage: bool = Field(alias="isStage")


class CompositeObservation(BaseModel):
    """The text an agent reads, and what it describes."""

    model_config = ConfigDict(frozen=True, populate_by_name=True)

    text: str
    editing_target: str = Field(alias="editingTarget")
    block_count: int = Field(alias="blockCount")
    targets: list[TargetName]
    """Every target of the project (stage first), for switching with select_sprite/select_stage."""


ElementSource = Literal["dom", "ocr"]


class Element(BaseModel):
    """One entry of the list an agent reads; ``index`` is how it names the element."""

    model_config = ConfigDict(frozen=True)

    index: int
    """Position in the list, 0-based; valid only for the observation it came with."""

    type: str
    """A DOM type (``blocks``, ``buttons``, ...) or ``text`` for text read off the screen."""

    text: str
    x: int
    """Left edge in page pixels (the screenshot's, at device pixel ratio 1)."""

    y: int
    """Top edge in page pixels."""

    width: int
    height: int
    source: ElementSource = "dom"
    """``dom``: from the page itself; ``ocr``: recognised in the screenshot."""

    opcode: str | None = None
    block_id: str | None = None

    @property
    def center(self) -> tuple[float, float]:
        """The point an index resolves to."""
        return self.x + self.width / 2, self.y + self.height / 2


class ObservationTimings(BaseModel):
    """Milliseconds per phase of one primitive observation."""

    settle_ms: float = 0.0
    screenshot_ms: float = 0.0
    dom_ms: float = 0.0
    ocr_ms: float = 0.0
    total_ms: float = 0.0


class PrimitiveObservation(BaseModel):
    """One observation: the PNG, the element list and its rendering for a prompt."""

    model_config = ConfigDict(frozen=True)

    screenshot_png: bytes = Field(repr=False)
    elements: list[Element]
    text: str
    """The element list as an agent reads it, one ``index  type  text  (x, y) WxH`` line each."""

    settled: bool
    """False when the page was still changing when the settle wait ran out."""

    warnings: list[str] = Field(default_factory=list)
    timings: ObservationTimings = Field(default_factory=ObservationTimings)


Observation = CompositeObservation | PrimitiveObservation
"""What an environment shows an agent before each action, by mode."""


class StepObservation(BaseModel):
    """What the agent was shown before a step, as its trajectory keeps it (for viewers and debugging).

    Kept whatever the agent does with it, so a trajectory shows what a plugin agent saw too.
    """

    model_config = ConfigDict(frozen=True)

    text: str | None = None
    """Composite mode: the project as the agent read it (primitive: None, ``elements`` say it)."""

    screenshot: str | None = None
    """Primitive mode: SHA-256 of the PNG, stored with the trajectory's images."""

    elements: list[Element] = Field(default_factory=list)
    """Primitive mode: the element list as the agent got it."""

    @classmethod
    def of(cls, observation: Observation) -> tuple[StepObservation, bytes | None]:
        """The record of ``observation``, and the screenshot it refers to (None in composite mode)."""
        if isinstance(observation, CompositeObservation):
            return cls(text=observation.text), None
        digest = hashlib.sha256(observation.screenshot_png).hexdigest()
        return cls(screenshot=digest, elements=observation.elements), observation.screenshot_png


class ObservationSettings(BaseModel):
    """How primitive observations are made; part of a primitive job's identity."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    ocr: Literal["rapidocr", "paddleocr", "none"] = "rapidocr"
    ocr_scope: Literal["pixels", "screen"] = "pixels"
    """``pixels``: OCR only where the DOM has no text; ``screen``: the whole frame, like upstream."""

    ocr_min_score: float = Field(default=0.5, ge=0, le=1)
    paddle_det_model_dir: Path | None = None
    paddle_rec_model_dir: Path | None = None

    @model_validator(mode="after")
    def _paddle_needs_models(self) -> ObservationSettings:
        if self.ocr == "paddleocr" and (self.paddle_det_model_dir is None or self.paddle_rec_model_dir is None):
            raise ValueError(
                "ocr 'paddleocr' needs paddle_det_model_dir and paddle_rec_model_dir (local PaddleOCR model "
                "directories: it cannot download weights offline)"
            )
        return self
