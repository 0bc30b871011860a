"""The optional PaddleOCR 3.x backend (the paper's engine), offline from local model directories only.

Offline, PaddleOCR with default settings probes model hosts and then downloads for up to ~25 s before an
opaque failure. This backend therefore refuses to start unless both model directories are complete, and
checks that before importing paddle. Order of checks, all in the constructor and all cheap:

1. each model directory holds ``inference.yml``, ``inference.pdiparams`` and ``inference.json`` (or
   ``.pdmodel``): the user's own configuration, so its error names the exact file;
2. ``paddleocr`` is importable (looked up, not imported): otherwise the error names the extra to install.

The engine itself (``import paddleocr`` is about 2 s) is built on the first ``recognize``.
"""

from __future__ import annotations

import importlib.util
import os
import threading
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from workers.contract import OCRError
from workers.node import user_cache_dir
from workers.ocr._backend import TextBox, box_from_quad, check_image

PADDLE_EXTRA = "pip install 'scratchworld-dist[paddle]'"


def default_cache_dir() -> Path:
    """Where PaddleX may write its caches, instead of the home directory."""
    return user_cache_dir() / "scratchworld" / "paddlex"


def check_model_dir(model_dir: Path, role: str) -> str | None:
    """Fail on an incomplete Paddle model directory; return the model name its ``inference.yml`` declares."""
    config = model_dir / "inference.yml"
    if not config.is_file():
        raise OCRError(
            f"PaddleOCR {role} model directory {model_dir} has no inference.yml; "
            "point it at an exported Paddle inference model (inference.yml, inference.json, inference.pdiparams)"
        )
    if not (model_dir / "inference.pdiparams").is_file():
        raise OCRError(f"PaddleOCR {role} model directory {model_dir} has no inference.pdiparams")
    if not ((model_dir / "inference.json").is_file() or (model_dir / "inference.pdmodel").is_file()):
        raise OCRError(f"PaddleOCR {role} model directory {model_dir} has neither inference.json nor inference.pdmodel")
    try:
        declared = yaml.safe_load(config.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, yaml.YAMLError) as exc:
        raise OCRError(f"PaddleOCR {role} model config {config} is unreadable: {exc}") from exc
    name = declared.get("Global", {}).get("model_name") if isinstance(declared, dict) else None
    return name if isinstance(name, str) else None


def boxes_from_paddle(result: Mapping[str, Any], shape: tuple[int, ...], min_score: float) -> list[TextBox]:
    """Map one PaddleOCR 3.x page result (dict-like: rec_texts, rec_scores, rec_polys) to text boxes."""
    texts, scores, polys = result["rec_texts"], result["rec_scores"], result["rec_polys"]
    return [
        box_from_quad(text, score, poly, shape)
        for text, score, poly in zip(texts, scores, polys, strict=True)
        if score >= min_score and text.strip()
    ]


class PaddleOCRBackend:
    """PaddleOCR 3.x on CPU from local det/rec model directories; needs the ``paddle`` extra."""

    name = "paddleocr"

    def __init__(
        self,
        det_model_dir: Path | str,
        rec_model_dir: Path | str,
        min_score: float = 0.5,
        cache_dir: Path | str | None = None,
    ) -> None:
        self.det_model_dir = Path(det_model_dir)
        self.rec_model_dir = Path(rec_model_dir)
        self.min_score = min_score
        self.cache_dir = Path(cache_dir) if cache_dir is not None else default_cache_dir()
        # PaddleX refuses a directory whose model differs from the one it would pick by default, so pass
        # the names the directories declare; lang is then moot (the rec model fixes the language).
        self._det_model_name = check_model_dir(self.det_model_dir, "detection")
        self._rec_model_name = check_model_dir(self.rec_model_dir, "recognition")
        if importlib.util.find_spec("paddleocr") is None:
            raise OCRError(f"the paddleocr backend needs paddleocr and paddlepaddle: {PADDLE_EXTRA}")
        self._engine: Any = None
        self._lock = threading.Lock()

    def recognize(self, image: np.ndarray) -> list[TextBox]:
        """Read every text line of a BGR image; lines scoring under ``min_score`` are dropped."""
        check_image(image)
        if image.size == 0:
            return []
        with self._lock:
            engine = self._engine if self._engine is not None else self._start()
            try:
                results = list(engine.predict(image))
            except Exception as exc:
                raise OCRError(f"paddleocr failed on a {image.shape[1]}x{image.shape[0]} image: {exc}") from exc
        return [box for result in results for box in boxes_from_paddle(result, image.shape, self.min_score)]

    def _start(self) -> Any:
        """Build the engine; called under the lock. The environment must be set before paddle is imported."""
        os.environ["PADDLE_PDX_DISABLE_MODEL_SOURCE_CHECK"] = "True"
        os.environ["PADDLE_PDX_CACHE_HOME"] = str(self.cache_dir)
        try:
            from paddleocr import PaddleOCR
        except ImportError as exc:
            raise OCRError(f"paddleocr cannot be imported ({exc}): {PADDLE_EXTRA}") from exc
        try:
            engine = PaddleOCR(
                text_detection_model_name=self._det_model_name,
                text_detection_model_dir=str(self.det_model_dir),
                text_recognition_model_name=self._rec_model_name,
                text_recognition_model_dir=str(self.rec_model_dir),
                use_doc_orientation_classify=False,
                use_doc_unwarping=False,
                use_textline_orientation=False,
                device="cpu",
            )
        except Exception as exc:
            raise OCRError(
                f"paddleocr could not start from {self.det_model_dir} and {self.rec_model_dir}: {exc}"
            ) from exc
        self._engine = engine
        return engine
