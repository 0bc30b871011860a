"""Prints what OCR of a primitive episode's first observation costs per region, and what it reads, per detection scale.

    .venv/bin/python benchmarks/ocr_regions.py [SUITE_DIR] [--max-det-scale 5,23] [--tasks a,b] [--at-once 2]

For each task of the suite (ours by default), one editor loads the task's initial project as a primitive
episode does (the small stage), takes the observation's screenshot and its pixel-only regions (the stage,
picture tiles), and reads each region with rapidocr under each ``--max-det-scale`` (how many times a region
may be scaled up before detection; 23 lets a 32x32 tile reach rapidocr's own 736, as before the limit).
Prints per region its kind and size, then per scale the CPU-s of the read (this process's, one read at a
time) and the texts found, and at the end the median CPU-s per kind of region for each scale. ``--at-once K``:
each read is made by K engines at once, in threads of their own (as K workers of a node read one stage at the
start of their episodes), and its CPU-s is this process's over the K reads, divided by K.
"""

from __future__ import annotations

import argparse
import asyncio
import base64
import statistics
import time
from collections import defaultdict
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import cv2
import numpy as np

from scratchworld_dist.suites import load_suite
from workers.editor import BrowserConfig, BrowserSession
from workers.kinds.tasks._runner import PRIMITIVE_STAGE
from workers.ocr import RapidOCRBackend
from workers.primitive._elements import read_dom

REPO = Path(__file__).resolve().parents[1]


async def main(suite_dir: Path, scales: list[float], task_ids: set[str] | None, at_once: int) -> None:
    backends = {scale: [RapidOCRBackend(max_det_scale=scale) for _ in range(at_once)] for scale in scales}
    threads = ThreadPoolExecutor(at_once)
    for engines in backends.values():  # the engines start outside the measured reads
        for backend in engines:
            backend.recognize(np.full((32, 32, 3), 255, np.uint8))
    costs: dict[tuple[str, float], list[float]] = defaultdict(list)
    tasks = [task for task in load_suite(suite_dir).tasks if task_ids is None or task.id in task_ids]
    async with BrowserSession(BrowserConfig()) as session:
        editor = await session.open_editor()
        devtools = await editor.page.context.new_cdp_session(editor.page)
        try:
            for task in tasks:
                await editor.load_project(task.initial_project.read_bytes())
                await editor.set_stage_size(PRIMITIVE_STAGE)
                shot = await devtools.send("Page.captureScreenshot", {"format": "png", "optimizeForSpeed": True})
                image = cv2.imdecode(np.frombuffer(base64.b64decode(shot["data"]), np.uint8), cv2.IMREAD_COLOR)
                for region in (await read_dom(editor)).pixel_regions:
                    top, left = max(region.y, 0), max(region.x, 0)
                    crop = np.ascontiguousarray(image[top : region.y + region.height, left : region.x + region.width])
                    reads = []
                    for scale, engines in backends.items():
                        started = time.process_time()
                        boxes, *_ = threads.map(RapidOCRBackend.recognize, engines, [crop] * at_once)
                        cpu_s = (time.process_time() - started) / at_once
                        costs[(region.kind, scale)].append(cpu_s)
                        reads.append(f"x{scale:g} {cpu_s:.2f} CPU-s {[box.text for box in boxes]}")
                    size = f"{crop.shape[1]}x{crop.shape[0]}"
                    print(f"{task.id:28s} {region.kind:6s} {size:8s} " + " | ".join(reads), flush=True)
                editor.uses += 1
                await editor.recycle()
        finally:
            await editor.close()
    print("median CPU-s per read:")
    for kind in sorted({kind for kind, _ in costs}):
        figures = ", ".join(f"x{scale:g} {statistics.median(costs[(kind, scale)]):.2f}" for scale in scales)
        print(f"  {kind:6s} ({len(costs[(kind, scales[0])])} regions): {figures}")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("suite", nargs="?", type=Path, default=REPO / "tasks")
    parser.add_argument("--max-det-scale", default="5,23")
    parser.add_argument("--tasks", default=None, help="task ids, comma-separated (default: all)")
    parser.add_argument("--at-once", type=int, default=1, help="engines reading each region at once (default 1)")
    args = parser.parse_args()
    if args.at_once < 1:
        parser.error("--at-once must be at least 1")
    asyncio.run(
        main(
            args.suite,
            [float(scale) for scale in args.max_det_scale.split(",")],
            set(args.tasks.split(",")) if args.tasks else None,
            args.at_once,
        )
    )
