"""Measuring what one more editor costs this node while its agent waits on a model (see ``workers.node``).

The figures feed ``derive_slots``. Measuring opens a browser and a few editors, so a node measures
once per harness and keeps the figures in the user's cache directory.
"""

from __future__ import annotations

import asyncio
import json
import time
from pathlib import Path

from pydantic import ValidationError

from workers.contract import ClockMode, EpisodeClock
from workers.editor._browser import BrowserConfig, BrowserSession
from workers.node import EditorCost, browser_usage, user_cache_dir

CALIBRATION_EDITORS = 3
"""Editors opened to measure one editor's marginal cost (several, so shared pages are split fairly)."""

CALIBRATION_WINDOW_S = 3.0
"""How long the waiting pages are watched for their CPU."""


async def measure_editor_cost(clock: ClockMode, harness: str = "", editors: int = CALIBRATION_EDITORS) -> EditorCost:
    """Open ``editors`` editors in a fresh browser, let them wait as an agent's pages do, and measure.

    Only that browser's processes are counted: the caller's other browsers (a worker's own, or Ray
    workers' under it) may be busy meanwhile, and one lent page on the real clock costs about what
    is measured here.
    """
    async with BrowserSession(BrowserConfig()) as session:
        await session.responsive()  # the browser process is up: its own memory is the baseline
        root = await session.browser_pid()
        empty = browser_usage(root)
        pages = [await session.open_editor() for _ in range(editors)]
        for page in pages:
            if clock == "virtual":  # as after an episode's start: paused until the next action
                await page.start_episode_clock(EpisodeClock(mode="virtual"))
                await page.advance_clock(EpisodeClock().start_ms)
            await page.collect_garbage()  # as the episode runner does once its page first waits for a model
        before, started = browser_usage(root), time.monotonic()
        await asyncio.sleep(CALIBRATION_WINDOW_S)  # a measurement window: the pages' CPU over time
        after = browser_usage(root)
        cores = after.cpu_cores_since(before, time.monotonic() - started)
        return EditorCost(
            clock=clock,
            cpu_cores=cores / editors,
            pss_bytes=max(after.pss_bytes - empty.pss_bytes, 0) // editors,
            harness=harness,
            measured_at=time.time(),
        )


def cost_cache_path() -> Path:
    return user_cache_dir() / "scratchworld_dist" / "editor-cost.json"


def cached_editor_cost(clock: ClockMode, harness: str, path: Path | None = None) -> EditorCost:
    """This node's measured cost for ``clock``, measured once per harness and kept in the user's cache."""
    path = path or cost_cache_path()
    known: dict[str, EditorCost] = {}
    try:
        raw = json.loads(path.read_text())
        known = {key: EditorCost.model_validate(value) for key, value in raw.items()}
    except (OSError, ValueError, ValidationError, AttributeError):
        pass  # nothing measured yet, or a damaged file: measure again
    cost = known.get(clock)
    if cost is None or cost.harness != harness:
        cost = asyncio.run(measure_editor_cost(clock, harness))
        known[clock] = cost
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(json.dumps({key: value.model_dump(mode="json") for key, value in known.items()}))
        except OSError:
            pass  # a read-only home: measured again next time
    return cost
