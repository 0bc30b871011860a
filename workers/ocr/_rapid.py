"""The default backend: rapidocr 3.x on onnxruntime, with the PP-OCRv6 models bundled in its wheel."""

from __future__ import annotations

import importlib.util
import logging
import threading
from pathlib import Path
from typing import Any

import numpy as np

from workers.contract import OCRError
from workers.ocr._backend import TextBox, box_from_quad, check_image

DET_MODEL = "PP-OCRv6_det_small.onnx"
REC_MODEL = "PP-OCRv6_rec_small.onnx"
"""The models rapidocr==3.10.0 ships; any other choice makes rapidocr download at run time."""

_RAPIDOCR_LOGGER = "RapidOCR"


def bundled_models_dir() -> Path:
    """The ``models`` directory inside the installed rapidocr package, located without importing it."""
    spec = importlib.util.find_spec("rapidocr")
    if spec is None or not spec.submodule_search_locations:
        raise OCRError("rapidocr is not installed; install the project's dependencies (rapidocr==3.10.0)")
    return Path(next(iter(spec.submodule_search_locations))) / "models"


class RapidOCRBackend:
    """rapidocr with its bundled det/rec models pinned by path, so no configuration can trigger a download.

    Construction only checks that onnxruntime and the model files exist; the engine (about 0.8 s of
    imports) is built on the first ``recognize``. Calls are serialised by a lock: one engine, one image
    at a time, with ``threads`` intra-op threads each.

    Before detection rapidocr scales an image up until its short side is ``det_limit_side_len`` (736),
    which suits full frames but would make a small crop cost as much as a whole screenshot or more: a
    220x40 crop read at 4048x736, a 32x32 sprite tile at 736x736 (0.6-0.7 CPU-s). So an image is scaled
    up at most ``max_det_scale`` times (a 32x32 tile to 160x160, about 0.1 CPU-s). Only detection is
    scaled (recognition reads the found lines at the image's own pixels), and the default 5 leaves the
    primitive stage (240x180, scaled 4.1 times) and whole frames (1.02 times) read as before. A lower
    limit side speeds up larger crops too but misses more small digits.

    The engine runs on onnxruntime sessions built here (``_sessions``), which rapidocr takes through its
    custom-session hook: the same options its own would have, but with the intra-op threads sleeping
    between operators instead of spinning. A spinning thread keeps a core busy while it waits, which on a
    loaded node takes that core from the browsers: two stage reads at once (a 240x180 stage, two
    processes, 2 cores) cost 1.23-1.28 CPU-s each spinning and 0.82-0.83 without, with the same boxes
    (the thread count, and so the arithmetic, is unchanged).
    """

    name = "rapidocr"

    def __init__(
        self,
        threads: int = 2,
        min_score: float = 0.5,
        det_limit_side_len: int = 736,
        max_det_scale: float = 5.0,
        models_dir: Path | None = None,
    ) -> None:
        if threads < 1:
            raise ValueError(f"threads must be at least 1, got {threads}")
        if max_det_scale < 1:
            raise ValueError(f"max_det_scale must be at least 1, got {max_det_scale}")
        self.threads = threads
        self.min_score = min_score
        self.det_limit_side_len = det_limit_side_len
        self.max_det_scale = max_det_scale
        models = models_dir if models_dir is not None else bundled_models_dir()
        self._det_model = models / DET_MODEL
        self._rec_model = models / REC_MODEL
        for path in (self._det_model, self._rec_model):
            if not path.is_file():
                raise OCRError(f"rapidocr model file missing: {path} (reinstall rapidocr==3.10.0, which bundles it)")
        if importlib.util.find_spec("onnxruntime") is None:
            # rapidocr does not depend on onnxruntime and would only fail on first use.
            raise OCRError("onnxruntime is not installed; rapidocr needs it: pip install onnxruntime==1.31.1")
        self._engine: Any = None
        self._lock = threading.Lock()

    def recognize(self, image: np.ndarray) -> list[TextBox]:
        """Read every text line of a BGR image; lines scoring under ``min_score`` are dropped."""
        check_image(image)
        if image.size == 0:
            return []
        with self._lock:
            engine = self._engine if self._engine is not None else self._start()
            engine.text_det.limit_side_len = self.detection_side(image)
            try:
                output = engine(image)
            except Exception as exc:
                raise OCRError(f"rapidocr failed on a {image.shape[1]}x{image.shape[0]} image: {exc}") from exc
        if output.txts is None or output.boxes is None:
            return []
        return [
            box_from_quad(text, score, quad, image.shape)
            for quad, text, score in zip(output.boxes, output.txts, output.scores, strict=True)
            if score >= self.min_score and text.strip()
        ]

    def detection_side(self, image: np.ndarray) -> int:
        """The short side detection scales ``image`` up to: ``det_limit_side_len``, or less for a small image."""
        return min(self.det_limit_side_len, max(32, int(self.max_det_scale * min(image.shape[:2]))))

    def _sessions(self) -> tuple[Any, Any]:
        """The detector's and recognizer's onnxruntime sessions: rapidocr's own options (``config.yaml``'s
        ``EngineConfig.onnxruntime`` with the threads asked for), threads that do not spin."""
        import onnxruntime

        options = onnxruntime.SessionOptions()
        options.log_severity_level = 4
        options.enable_cpu_mem_arena = False
        options.graph_optimization_level = onnxruntime.GraphOptimizationLevel.ORT_ENABLE_ALL
        options.intra_op_num_threads = self.threads
        options.inter_op_num_threads = 1
        options.add_session_config_entry("session.intra_op.allow_spinning", "0")
        providers = [("CPUExecutionProvider", {"arena_extend_strategy": "kSameAsRequested"})]
        detector, recognizer = (
            onnxruntime.InferenceSession(str(model), sess_options=options, providers=providers)
            for model in (self._det_model, self._rec_model)
        )
        return detector, recognizer

    def _start(self) -> Any:
        """Build the engine; called under the lock."""
        try:
            from omegaconf import flag_override
            from rapidocr import RapidOCR
        except ImportError as exc:
            raise OCRError(f"rapidocr cannot be imported ({exc}); install rapidocr==3.10.0 and onnxruntime") from exc
        params = {
            "Global.use_cls": False,  # screenshots hold no upside-down text
            "Global.text_score": self.min_score,
            "Global.log_level": "error",
            "Det.model_path": str(self._det_model),
            "Rec.model_path": str(self._rec_model),
            "Det.limit_side_len": 32,  # set for each read (``detection_side``); the start-up read is tiny
        }
        try:
            engine = RapidOCR(params=params)
            # rapidocr builds a model's session on first use from ``Det.session``/``Rec.session`` when set;
            # only a config that allows objects holds one.
            with flag_override(engine.cfg, "allow_objects", True):
                engine.cfg.Det.session, engine.cfg.Rec.session = self._sessions()
            # An empty frame makes rapidocr log "The text detection result is empty" at WARNING on its own
            # non-propagating logger; an empty frame is a normal result here, not a warning.
            logging.getLogger(_RAPIDOCR_LOGGER).setLevel(logging.ERROR)
            # The detector is built on the first read; built now, each read can set its scale (``detection_side``).
            engine(np.full((32, 32, 3), 255, np.uint8))
        except Exception as exc:
            raise OCRError(
                f"rapidocr could not start with {self._det_model.name}, {self._rec_model.name}: {exc}"
            ) from exc
        if getattr(engine, "text_det", None) is None:
            raise OCRError("rapidocr's text detector did not start (rapidocr==3.10.0 is the version this expects)")
        self._engine = engine
        return engine
