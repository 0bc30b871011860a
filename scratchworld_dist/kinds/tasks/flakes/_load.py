"""CPU load as a perturbation: busy processes of our own, started for a while and then ended by id."""

from __future__ import annotations

import os
import subprocess
import sys
from collections.abc import Iterator
from contextlib import contextmanager

_BUSY = "while True:\n    pass\n"


@contextmanager
def cpu_load(processes: int) -> Iterator[None]:
    """``processes`` Python processes spinning on a core each until the block ends (0: none)."""
    started: list[subprocess.Popen[bytes]] = []
    try:
        for _ in range(processes):
            started.append(subprocess.Popen([sys.executable, "-c", _BUSY], stdin=subprocess.DEVNULL))
        yield
    finally:
        for process in started:
            process.kill()
        for process in started:
            process.wait()


def load_average() -> float:
    """The machine's one-minute load average, recorded with each run."""
    return round(os.getloadavg()[0], 2)
