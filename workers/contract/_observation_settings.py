"""Settings of primitive observations: part of a primitive job's identity, validated by the driver."""

from __future__ import annotations

from pathlib import Path
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator


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
