"""Prints p50/p95 of a primitive observation and its parts: screenshot, DOM list, OCR, whole, and the DOM pass alone.

    .venv/bin/python benchmarks/primitive_observation.py [--project PATH.sb3] [--rounds 30] [--ocr-scope pixels]

Each round observes, then changes the page the way an agent step does (a category click that
scrolls the palette; every third round also a scroll of the workspace). Target: whole observation p50 <= 400 ms
on a 2-core machine with the default settings (rapidocr, OCR only where the DOM has no text); the DOM pass
alone, timed in the page (``dom pass``, a pass after each observation, on the settled page), p50 < 50 ms.
``--ocr-scope screen`` measures the upstream-style whole-frame OCR for comparison.
"""

from __future__ import annotations

import argparse
import asyncio
import statistics
import time
from pathlib import Path

from workers.contract import ObservationSettings, PrimitiveObservation
from workers.editor import BrowserSession
from workers.primitive import Gestures, PrimitiveObserver, region_ocr
from workers.primitive._elements import read_dom

REPO = Path(__file__).resolve().parents[1]
DEFAULT_PROJECT = REPO / "tasks" / "extend" / "quiz_score" / "initial.sb3"


def percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, round(q * (len(ordered) - 1)))]


def _by_text(observation: PrimitiveObservation, kind: str, text: str) -> int:
    return next(e.index for e in observation.elements if e.type == kind and e.text == text)


async def main(project: Path, sb3: bytes, rounds: int, scope: str) -> None:
    settings = ObservationSettings(ocr_scope=scope)  # type: ignore[arg-type]
    ocr = region_ocr(settings)
    laps: dict[str, list[float]] = {"screenshot": [], "dom": [], "ocr": [], "settle": [], "whole": [], "dom pass": []}
    async with BrowserSession() as session, session.editor() as editor:
        await editor.load_project(sb3)
        await editor.set_stage_size("small")
        observer = PrimitiveObserver(settings, ocr)
        gestures = Gestures(editor.page)
        started = time.perf_counter()
        first = await observer.observe(editor)
        print(f"first observation (OCR engine start included): {(time.perf_counter() - started) * 1000:.0f} ms")
        categories = [e.text for e in first.elements if e.type == "category_menu_item"]
        for round_index in range(rounds):
            observation = await observer.observe(editor)
            gestures.elements = observation.elements
            for part in ("screenshot", "dom", "ocr", "settle"):
                laps[part].append(getattr(observation.timings, f"{part}_ms"))
            laps["whole"].append(observation.timings.total_ms)
            laps["dom pass"].append((await read_dom(editor)).elapsed_ms)
            # Change the page the way agents do between observations.
            category = categories[round_index % len(categories)]
            await gestures.execute("click", {"index": _by_text(observation, "category_menu_item", category)})
            if round_index % 3 == 2:
                await gestures.execute("scroll", {"direction": "down", "amount": 120, "x": 650, "y": 400})
    print(f"{len(laps['whole'])} observations of {project.name}, ocr_scope={scope}, {len(first.elements)} elements")
    print(f"{'part':<12}{'p50 ms':>10}{'p95 ms':>10}{'mean ms':>10}")
    for part, values in laps.items():
        p50, p95 = percentile(values, 0.5), percentile(values, 0.95)
        print(f"{part:<12}{p50:>10.1f}{p95:>10.1f}{statistics.fmean(values):>10.1f}")
    if ocr is not None:
        print(f"OCR region cache: {ocr.hits} hits, {ocr.misses} misses")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--project", type=Path, default=DEFAULT_PROJECT)
    parser.add_argument("--rounds", type=int, default=30)
    parser.add_argument("--ocr-scope", choices=["pixels", "screen"], default="pixels")
    options = parser.parse_args()
    asyncio.run(main(options.project, options.project.read_bytes(), options.rounds, options.ocr_scope))
