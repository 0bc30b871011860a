"""The driver's progress: done, outcomes, in flight, rate, ETA and cost.

On a terminal (``rich``) it is one live line, redrawn twice a second. Off one (``plain``: nohup, SLURM, CI logs,
a pipe) a live display would print only its last frame when the sweep ends, so the same line is printed whole,
with the time, every ``interval_s`` and once at the end. ``auto`` picks by the console; ``none`` prints nothing.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from datetime import datetime
from typing import Literal, get_args

from pydantic import BaseModel, Field
from rich.console import Console
from rich.live import Live
from rich.text import Text

from scratchworld_dist.scheduling._scheduler import SchedulerStats

ProgressMode = Literal["auto", "rich", "plain", "none"]
PROGRESS_MODES: tuple[str, ...] = get_args(ProgressMode)

PLAIN_INTERVAL_S = 30.0
"""How often a plain progress line is printed by default."""


class ProgressOptions(BaseModel):
    """How a run shows its progress (``run --progress``, ``--progress-interval``)."""

    mode: ProgressMode = "auto"
    interval_s: float = Field(default=PLAIN_INTERVAL_S, gt=0)
    """Seconds between plain progress lines."""


def _duration(seconds: float) -> str:
    seconds = int(seconds)
    return f"{seconds // 3600}:{seconds % 3600 // 60:02d}:{seconds % 60:02d}"


class ProgressLine:
    """Renders ``SchedulerStats`` for a run of ``total`` jobs."""

    def __init__(self, stats: SchedulerStats, total: int) -> None:
        self.stats = stats
        self.total = total
        self.started = time.monotonic()

    def __rich__(self) -> Text:
        stats, elapsed = self.stats, time.monotonic() - self.started
        done = sum(stats.outcomes.values())
        rate = done / elapsed if elapsed > 0 else 0.0
        eta = _duration((self.total - done) / rate) if rate > 0 else "?"
        line = Text()
        line.append(f"{done}/{self.total} done  ", style="bold")
        line.append(f"passed {stats.outcomes['passed']}  ", style="green")
        line.append(f"failed {stats.outcomes['failed']}  ", style="yellow")
        line.append(f"error {stats.outcomes['error']}  ", style="red")
        line.append(f"in flight {stats.in_flight}  retried {stats.retried}  ")
        if stats.warming:
            line.append(f"{stats.warming} worker(s) opening editors  ", style="cyan")
        if stats.paused:
            line.append(f"{stats.paused} worker(s) short of memory  ", style="red")
        line.append(f"{rate * 60:.1f} jobs/min  ETA {eta}  elapsed {_duration(elapsed)}  ${stats.cost_usd:.4f}")
        return line

    def plain(self) -> str:
        """The line as text, after the wall-clock time (a log line)."""
        return f"[{datetime.now().strftime('%H:%M:%S')}] progress: {self.__rich__().plain}"


def shown_mode(mode: ProgressMode, console: Console) -> ProgressMode:
    """What ``auto`` means on ``console``: the live line on a terminal, plain lines elsewhere."""
    if mode != "auto":
        return mode
    return "rich" if console.is_terminal else "plain"


@contextmanager
def live_progress(
    stats: SchedulerStats,
    total: int,
    console: Console,
    mode: ProgressMode = "auto",
    interval_s: float = PLAIN_INTERVAL_S,
) -> Iterator[None]:
    """Show the progress of ``total`` jobs while the block runs, as ``mode`` says."""
    line = ProgressLine(stats, total)
    shown = shown_mode(mode, console)
    if shown == "rich":
        with Live(line, console=console, refresh_per_second=2, transient=False):
            yield
        if not console.is_terminal:
            console.print()  # Live leaves its last line open when output goes to a file
        return
    if shown == "none":
        yield
        return
    stop = threading.Event()

    def every_interval() -> None:
        while not stop.wait(interval_s):
            console.print(line.plain(), markup=False, highlight=False)

    printer = threading.Thread(target=every_interval, name="plain-progress", daemon=True)
    printer.start()
    try:
        yield
    finally:
        stop.set()
        printer.join()
        console.print(line.plain(), markup=False, highlight=False)
