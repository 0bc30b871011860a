"""OCR backends and the region cache: real rapidocr on rendered text, small real backends for the cache."""

from __future__ import annotations

import logging
import sys
import threading
import time
from pathlib import Path

import cv2
import numpy as np
import pytest

from workers.contract import OCRError
from workers.ocr import PaddleOCRBackend, RapidOCRBackend, Region, RegionOCR, TextBox, ocr_backend
from workers.ocr._backend import box_from_quad
from workers.ocr._paddle import boxes_from_paddle

FONT = cv2.FONT_HERSHEY_SIMPLEX
LINES = [("move 10 steps", (20, 50)), ("Score: 42", (250, 120)), ("when clicked", (40, 200))]


@pytest.fixture(scope="module")
def rapid() -> RapidOCRBackend:
    """One engine for the module; the first recognize pays its start-up."""
    return RapidOCRBackend(threads=2)


def render(lines: list[tuple[str, tuple[int, int]]], background: tuple[int, int, int], ink: tuple[int, int, int]):
    """Draw text lines; return the image and each line's drawn rectangle (x, y, width, height)."""
    image = np.full((240, 480, 3), background, np.uint8)
    drawn = {}
    for text, (x, baseline) in lines:
        (width, height), below = cv2.getTextSize(text, FONT, 0.8, 2)
        cv2.putText(image, text, (x, baseline), FONT, 0.8, ink, 2, cv2.LINE_AA)
        drawn[text] = (x, baseline - height, width, height + below)
    return image, drawn


def blank(height: int = 120, width: int = 320, colour: tuple[int, int, int] = (255, 255, 255)) -> np.ndarray:
    return np.full((height, width, 3), colour, np.uint8)


class FixedBackend:
    """Finds one fixed box in any non-blank crop, and records what it was given."""

    name = "fixed"

    def __init__(self) -> None:
        self.crops: list[np.ndarray] = []
        self.threads: list[int] = []

    def recognize(self, image: np.ndarray) -> list[TextBox]:
        self.crops.append(image.copy())
        self.threads.append(threading.get_ident())
        if (image == 255).all():
            return []
        return [TextBox(text="hello", score=0.9, x=1, y=2, width=3, height=4)]


class BrokenBackend:
    name = "broken"

    def __init__(self, error: Exception) -> None:
        self.error = error

    def recognize(self, image: np.ndarray) -> list[TextBox]:
        raise self.error


# -- rapidocr --------------------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("background", "ink"),
    [((255, 255, 255), (0, 0, 0)), ((191, 90, 76), (255, 255, 255)), ((26, 171, 255), (0, 0, 0))],
    ids=["white", "blue-block", "orange-block"],
)
def test_rapid_reads_rendered_text_where_it_was_drawn(rapid: RapidOCRBackend, background, ink) -> None:
    image, drawn = render(LINES, background, ink)

    boxes = rapid.recognize(image)

    joined = " | ".join(box.text for box in boxes).lower()
    for text, (x, y, width, height) in drawn.items():
        assert text.lower() in joined
        (box,) = [box for box in boxes if text.lower() in box.text.lower()]
        # The detector pads its quads a little; centres stay put.
        assert abs((box.x + box.width / 2) - (x + width / 2)) <= 5
        assert abs((box.y + box.height / 2) - (y + height / 2)) <= 5
        assert abs(box.x - x) <= 10
        assert abs(box.y - y) <= 10
        assert abs((box.x + box.width) - (x + width)) <= 10
        assert abs((box.y + box.height) - (y + height)) <= 10
        assert box.score >= rapid.min_score


def test_rapid_empty_image_is_quiet(rapid: RapidOCRBackend, caplog, capfd) -> None:
    rapid.recognize(render(LINES[:1], (255, 255, 255), (0, 0, 0))[0])  # engine started before we listen
    records: list[logging.LogRecord] = []
    listener = logging.Handler(logging.DEBUG)
    listener.emit = records.append  # type: ignore[method-assign]
    rapid_logger = logging.getLogger("RapidOCR")  # rapidocr's own logger does not propagate to caplog
    rapid_logger.addHandler(listener)
    try:
        with caplog.at_level(logging.DEBUG):
            assert rapid.recognize(blank(360, 640)) == []
            assert rapid.recognize(blank(360, 640, colour=(191, 90, 76))) == []
    finally:
        rapid_logger.removeHandler(listener)
    assert [r.getMessage() for r in records if r.levelno >= logging.WARNING] == []
    assert [r.getMessage() for r in caplog.records if r.levelno >= logging.WARNING] == []
    assert "detection result is empty" not in capfd.readouterr().err


def test_rapid_scales_a_small_crop_up_at_most_five_times_and_still_reads_it(rapid: RapidOCRBackend) -> None:
    # A 32x32 sprite tile would be detected at 736x736 (0.6-0.7 CPU-s); the stage and whole frames keep 736.
    assert rapid.detection_side(blank(32, 32)) == 160
    assert rapid.detection_side(blank(180, 240)) == 736
    assert rapid.detection_side(blank(720, 1280)) == 736
    assert rapid.detection_side(blank(4, 300)) == 32  # the detector's least input side
    image, drawn = render([("Score: 42", (4, 30))], (255, 255, 255), (0, 0, 0))
    x, y, width, height = drawn["Score: 42"]
    crop = np.ascontiguousarray(image[: y + height + 6, : x + width + 6])

    boxes = rapid.recognize(crop)

    assert [box.text.replace(" ", "") for box in boxes] == ["Score:42"]
    detector = rapid._engine.text_det  # the engine this read went through, as rapidocr itself resizes for it
    short = min(crop.shape[:2])
    assert detector.limit_side_len == 5 * short < 736
    assert min(detector.get_preprocess().resize(crop).shape[:2]) == round(5 * short / 32) * 32


def test_rapid_reads_through_sessions_that_do_not_spin_and_finds_what_rapidocr_alone_finds(
    rapid: RapidOCRBackend,
) -> None:
    from rapidocr import RapidOCR

    image, _ = render(LINES, (191, 90, 76), (255, 255, 255))
    boxes = rapid.recognize(image)
    engine = rapid._engine  # both models have read by now: the detector, and the recognizer on the lines found
    for model in (engine.text_det, engine.text_rec):
        options = model.session.session.get_session_options()
        assert options.get_session_config_entry("session.intra_op.allow_spinning") == "0"
        assert (options.intra_op_num_threads, options.inter_op_num_threads) == (2, 1)
    # rapidocr with the sessions it builds itself (which spin), the same models and threads, the same boxes
    own = RapidOCR(
        params={
            "Global.use_cls": False,
            "Global.log_level": "error",
            "Det.model_path": str(rapid._det_model),
            "Rec.model_path": str(rapid._rec_model),
            "Det.limit_side_len": rapid.detection_side(image),
            "EngineConfig.onnxruntime.intra_op_num_threads": 2,
            "EngineConfig.onnxruntime.inter_op_num_threads": 1,
        }
    )
    found = own(image)
    with pytest.raises(RuntimeError, match="allow_spinning"):  # unset: onnxruntime's default, threads that spin
        own.text_det.session.session.get_session_options().get_session_config_entry("session.intra_op.allow_spinning")
    assert len(boxes) == len(LINES)
    assert boxes == [
        box_from_quad(text, score, quad, image.shape)
        for quad, text, score in zip(found.boxes, found.txts, found.scores, strict=True)
        if score >= rapid.min_score and text.strip()
    ]


def test_rapid_refuses_a_detection_scale_below_one() -> None:
    with pytest.raises(ValueError, match="max_det_scale must be at least 1"):
        RapidOCRBackend(max_det_scale=0.5)


def test_rapid_rejects_non_bgr_images(rapid: RapidOCRBackend) -> None:
    with pytest.raises(ValueError, match="HxWx3 uint8"):
        rapid.recognize(np.zeros((20, 20), np.uint8))
    with pytest.raises(ValueError, match="HxWx3 uint8"):
        rapid.recognize(np.zeros((20, 20, 3), np.float32))


def test_rapid_names_a_missing_model_file(tmp_path: Path) -> None:
    with pytest.raises(OCRError, match=r"PP-OCRv6_det_small\.onnx"):
        RapidOCRBackend(models_dir=tmp_path)


def test_rapid_without_onnxruntime_says_to_install_it(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "onnxruntime", None)  # makes the package unimportable
    with pytest.raises(OCRError, match=r"onnxruntime is not installed.*pip install onnxruntime"):
        RapidOCRBackend()


# -- factory and paddle ----------------------------------------------------------------------------------------------


def test_factory_names_the_choices() -> None:
    with pytest.raises(OCRError, match=r"'nope'.*rapidocr, paddleocr"):
        ocr_backend("nope")
    backend = ocr_backend("rapidocr", threads=1, min_score=0.7)
    assert isinstance(backend, RapidOCRBackend)
    assert (backend.threads, backend.min_score) == (1, 0.7)
    assert isinstance(ocr_backend(), RapidOCRBackend)


def paddle_model_dir(root: Path, name: str) -> Path:
    """A directory with the files PaddleOCR needs to load a model offline (contents are not read by paddle here)."""
    root.mkdir()
    (root / "inference.yml").write_text(f"Global:\n  model_name: {name}\n")
    (root / "inference.json").write_text("{}")
    (root / "inference.pdiparams").write_bytes(b"")
    return root


def test_paddle_missing_model_dirs_fail_fast(tmp_path: Path) -> None:
    started = time.thread_time()  # this thread's CPU: loading a model burns it, a loaded machine only delays
    with pytest.raises(OCRError, match=r"detection model directory .*det has no inference\.yml"):
        ocr_backend("paddleocr", det_model_dir=tmp_path / "det", rec_model_dir=tmp_path / "rec")
    det = paddle_model_dir(tmp_path / "det", "PP-OCRv5_mobile_det")
    with pytest.raises(OCRError, match=r"recognition model directory .*rec has no inference\.yml"):
        PaddleOCRBackend(det_model_dir=det, rec_model_dir=tmp_path / "rec")
    (tmp_path / "rec").mkdir()
    (tmp_path / "rec" / "inference.yml").write_text("Global:\n  model_name: en_PP-OCRv5_mobile_rec\n")
    with pytest.raises(OCRError, match=r"rec has no inference\.pdiparams"):
        PaddleOCRBackend(det_model_dir=det, rec_model_dir=tmp_path / "rec")
    assert time.thread_time() - started < 2
    assert "paddle" not in sys.modules


def test_paddle_not_installed_names_the_extra(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "paddleocr", None)  # also holds where paddleocr is installed
    det = paddle_model_dir(tmp_path / "det", "PP-OCRv5_mobile_det")
    rec = paddle_model_dir(tmp_path / "rec", "en_PP-OCRv5_mobile_rec")
    with pytest.raises(OCRError, match=r"pip install 'scratchworld-dist\[paddle\]'"):
        PaddleOCRBackend(det_model_dir=det, rec_model_dir=rec)


class FakePaddleResult:
    """Dict-like like PaddleOCR 3.x's OCRResult, with the three keys the mapping reads."""

    def __init__(self, **fields: object) -> None:
        self.fields = fields

    def __getitem__(self, key: str) -> object:
        return self.fields[key]


def test_paddle_result_mapping() -> None:
    result = FakePaddleResult(
        rec_texts=["when clicked", "faint", "", "edge"],
        rec_scores=[0.98, 0.2, 0.99, 0.9],
        rec_polys=[
            np.array([[10, 20], [110, 21], [111, 40], [9, 39]], np.int16),
            np.array([[0, 0], [5, 0], [5, 5], [0, 5]], np.int16),
            np.array([[0, 0], [5, 0], [5, 5], [0, 5]], np.int16),
            np.array([[190, -3], [230, -3], [230, 12], [190, 12]], np.int16),
        ],
    )

    boxes = boxes_from_paddle(result, (100, 200, 3), min_score=0.5)  # type: ignore[arg-type]

    assert boxes == [
        TextBox(text="when clicked", score=0.98, x=9, y=20, width=102, height=20),
        TextBox(text="edge", score=0.9, x=190, y=0, width=10, height=12),  # clamped to the 200x100 image
    ]


# -- region cache ----------------------------------------------------------------------------------------------------


def test_moved_region_with_same_pixels_is_a_hit_translated(rapid: RapidOCRBackend) -> None:
    patch, drawn = render([("when clicked", (30, 70))], (26, 171, 255), (0, 0, 0))
    patch = patch[:120, :240]
    first, second = blank(480, 640), blank(480, 640)
    first[10:130, 20:260] = patch
    second[300:420, 400:640] = patch
    ocr = RegionOCR(rapid)

    found_first = ocr.recognize_regions(first, [Region(x=20, y=10, width=240, height=120)])
    found_second = ocr.recognize_regions(second, [Region(x=400, y=300, width=240, height=120)])

    assert (ocr.misses, ocr.hits) == (1, 1)
    assert "when clicked" in " ".join(box.text.lower() for box in found_first)
    x, y, _, _ = drawn["when clicked"]
    assert abs(min(box.x for box in found_first) - (20 + x)) <= 10
    assert abs(min(box.y for box in found_first) - (10 + y)) <= 10
    assert found_second == [box.model_copy(update={"x": box.x + 380, "y": box.y + 290}) for box in found_first]

    second[360, 500] = (0, 0, 255)  # one pixel changed: different content
    ocr.recognize_regions(second, [Region(x=400, y=300, width=240, height=120)])
    assert (ocr.misses, ocr.hits) == (2, 1)


def test_region_is_clipped_to_the_image() -> None:
    backend = FixedBackend()
    ocr = RegionOCR(backend)
    image = blank(100, 200)
    image[5:15, 5:15] = 0

    boxes = ocr.recognize_regions(image, [Region(x=-50, y=-20, width=100, height=60)])

    assert [crop.shape for crop in backend.crops] == [(40, 50, 3)]
    assert boxes == [TextBox(text="hello", score=0.9, x=1, y=2, width=3, height=4)]
    assert ocr.recognize_regions(image, [Region(x=150, y=-20, width=100, height=200)]) == []  # blank crop
    assert ocr.recognize_regions(image, [Region(x=300, y=0, width=10, height=10)]) == []  # wholly outside
    assert ocr.recognize_regions(image, [Region(x=0, y=0, width=0, height=10)]) == []
    assert [crop.shape for crop in backend.crops] == [(40, 50, 3), (100, 50, 3)]


def test_identical_regions_give_one_box() -> None:
    ocr = RegionOCR(FixedBackend())
    image = blank(100, 200)
    image[50, 50] = 0
    region = Region(x=40, y=30, width=60, height=40)

    boxes = ocr.recognize_regions(image, [region, region])

    assert boxes == [TextBox(text="hello", score=0.9, x=41, y=32, width=3, height=4)]
    assert (ocr.misses, ocr.hits) == (1, 1)


def test_least_recently_used_entry_is_evicted() -> None:
    backend = FixedBackend()
    ocr = RegionOCR(backend, max_entries=2)
    images = []
    for shade in (0, 60, 120):
        image = blank(20, 20)
        image[5, 5] = shade
        images.append(image)
    a, b, c = images

    for image in (a, b, a, c):  # a is used again before c arrives, so b is the oldest
        ocr.recognize(image)
    assert (ocr.misses, ocr.hits) == (3, 1)
    ocr.recognize(a)
    assert (ocr.misses, ocr.hits) == (3, 2)
    ocr.recognize(b)
    assert (ocr.misses, ocr.hits) == (4, 2)
    assert len(backend.crops) == 4


def test_backend_failure_becomes_ocr_error() -> None:
    cause = RuntimeError("session exploded")
    ocr = RegionOCR(BrokenBackend(cause))

    with pytest.raises(OCRError, match="'broken' failed: RuntimeError: session exploded") as caught:
        ocr.recognize(blank())
    assert caught.value.__cause__ is cause

    own = OCRError("model file missing")
    with pytest.raises(OCRError) as caught:
        RegionOCR(BrokenBackend(own)).recognize(blank())
    assert caught.value is own
    assert (ocr.misses, ocr.hits) == (1, 0)  # failures are not cached
    with pytest.raises(OCRError):
        ocr.recognize(blank())
    assert (ocr.misses, ocr.hits) == (2, 0)


async def test_async_recognition_runs_off_the_event_loop_thread() -> None:
    backend = FixedBackend()
    ocr = RegionOCR(backend)
    image = blank(100, 200)
    image[50, 50] = 0

    boxes = await ocr.arecognize_regions(image, [Region(x=40, y=30, width=60, height=40)])
    whole = await ocr.arecognize(image)

    assert boxes == [TextBox(text="hello", score=0.9, x=41, y=32, width=3, height=4)]
    assert whole == [TextBox(text="hello", score=0.9, x=1, y=2, width=3, height=4)]
    assert backend.threads
    assert threading.get_ident() not in backend.threads


class GatedBackend:
    """Blocks in ``recognize`` until released, then answers like ``FixedBackend`` or raises ``error``."""

    name = "gated"

    def __init__(self, error: Exception | None = None) -> None:
        self.entered = threading.Event()
        self.release = threading.Event()
        self.calls = 0
        self.error = error

    def recognize(self, image: np.ndarray) -> list[TextBox]:
        self.calls += 1
        self.entered.set()
        assert self.release.wait(10), "the test never released the backend"
        if self.error is not None:
            raise self.error
        return [TextBox(text="hello", score=0.9, x=1, y=2, width=3, height=4)]


def read_twice_at_once(ocr: RegionOCR, backend: GatedBackend, image: np.ndarray) -> list[object]:
    """Two threads read ``image``; the second arrives while the first is inside the backend. Each thread's boxes, or
    the exception it raised."""
    outcomes: list[object] = [None, None]

    def read(slot: int) -> None:
        try:
            outcomes[slot] = ocr.recognize(image)
        except Exception as exc:
            outcomes[slot] = exc

    first = threading.Thread(target=read, args=(0,))
    first.start()
    assert backend.entered.wait(10)
    second = threading.Thread(target=read, args=(1,))
    second.start()
    deadline = time.monotonic() + 10
    while ocr.shared < 1:  # the second read is waiting on the first
        assert time.monotonic() < deadline, "the second read never joined the first"
        time.sleep(0.001)
    backend.release.set()
    first.join(10)
    second.join(10)
    return outcomes


def test_a_read_of_pixels_already_being_read_waits_for_it_instead_of_reading_again() -> None:
    backend = GatedBackend()
    ocr = RegionOCR(backend)
    image = blank(40, 40)
    image[5, 5] = 0

    first, second = read_twice_at_once(ocr, backend, image)

    assert first == second == [TextBox(text="hello", score=0.9, x=1, y=2, width=3, height=4)]
    assert (backend.calls, ocr.misses, ocr.hits, ocr.shared) == (1, 1, 1, 1)
    assert ocr.recognize(image) == first and backend.calls == 1  # and it was cached


def test_a_failed_read_fails_the_reads_waiting_on_it_and_is_not_cached() -> None:
    backend = GatedBackend(RuntimeError("session exploded"))
    ocr = RegionOCR(backend)

    first, second = read_twice_at_once(ocr, backend, blank(40, 40))

    assert isinstance(first, OCRError) and "session exploded" in str(first)
    assert second is first
    assert (backend.calls, ocr.misses, ocr.shared) == (1, 1, 1)
    backend.error = None
    assert ocr.recognize(blank(40, 40)) != [] and backend.calls == 2  # the next read tries again
