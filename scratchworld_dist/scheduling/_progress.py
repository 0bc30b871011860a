"""The driver's live progress line: done, outcomes, in flight, rate, ETA and cost."""

from __future__ import annotations

import time
from collections.abc import Iterator
from contextlib import contextmanager

from rich.console import Console
from rich.live import Live
from rich.text import Text

from scratchworld_dist.scheduling._scheduler import SchedulerStats


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


@contextmanager
def live_progress(stats: SchedulerStats, total: int, console: Console) -> Iterator[None]:
    with Live(ProgressLine(stats, total), console=console, refresh_per_second=2, transient=False):
        yield
    if not console.is_terminal:
        console.print()  # Live leaves its last line open when output goes to a file
