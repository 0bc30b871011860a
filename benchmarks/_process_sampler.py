"""The density benchmark's sampler: the CPU seconds of every process below the benchmark's, by kind, twice a second.

Kinds tell where a sweep's cores go: the agents' Chromium processes by ``--type``, the browsers that judge, Playwright's
drivers, Ray's workers, the driver, the model server's process and Ray's own (``PROCESS_KINDS``).
"""

from __future__ import annotations

import os
import threading
import time
from dataclasses import dataclass, field

import psutil

INTERVAL_S = 0.5
"""Seconds between samples."""

PROCESS_KINDS = ("renderer", "browser", "gpu", "utility", "judge", "playwright", "worker", "driver", "model", "ray")
"""Where a sweep's cores go: the agents' Chromium processes by ``--type``, the idle-class browsers that judge
(every process of theirs), Playwright's Node drivers, Ray's workers (``ray::...``), this process (the driver and
the scheduler), the model server's process, and Ray's own (raylet, GCS...)."""


AGENT_BROWSER = ("renderer", "browser", "gpu", "utility")


def process_kind(process: psutil.Process) -> str:
    """One of ``PROCESS_KINDS`` for a process below this one (a browser's by ``--type``; ``Sampler`` tells the
    judges apart, as they move to the idle class after they start)."""
    name = process.name()
    if "chrom" in name:
        kind = next((arg.split("=", 1)[1] for arg in process.cmdline() if arg.startswith("--type=")), "browser")
        if kind == "gpu-process":
            return "gpu"
        return kind if kind in ("renderer", "browser") else "utility"
    if name.startswith("node"):  # Playwright's driver, "node-MainThread"
        return "playwright"
    if name.startswith("ray::"):
        return "worker"
    return "ray"


@dataclass(frozen=True)
class Sample:
    t: float
    by_kind: dict[str, float]
    """CPU seconds since sampling began per ``PROCESS_KINDS`` entry (per process, so exits lose no earlier CPU)."""

    @property
    def cpu_s(self) -> float:
        """CPU seconds the browsers spent since sampling began, the judges' included."""
        return sum(self.by_kind[kind] for kind in (*AGENT_BROWSER, "judge"))


@dataclass
class Sampler:
    """Samples the Chromium processes below this process every ``INTERVAL_S`` in a thread."""

    model_pid: int | None = None
    """The model server's process, told apart from Ray's own."""

    samples: list[Sample] = field(default_factory=list)
    _stop: threading.Event = field(default_factory=threading.Event)
    _cpu: dict[int, tuple[str, float]] = field(default_factory=dict)
    _totals: dict[str, float] = field(default_factory=lambda: dict.fromkeys(PROCESS_KINDS, 0.0))

    def __enter__(self) -> Sampler:
        self._thread = threading.Thread(target=self._loop, name="density-sampler", daemon=True)
        self._thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self._stop.set()
        self._thread.join()

    def _loop(self) -> None:
        while not self._stop.wait(INTERVAL_S):
            self.samples.append(self.sample())

    def sample(self) -> Sample:
        cpu: dict[int, tuple[str, float]] = {}
        me = psutil.Process()
        for process in [me, *me.children(recursive=True)]:
            try:
                with process.oneshot():
                    times = process.cpu_times()
                    known = self._cpu.get(process.pid)
                    if process.pid in (me.pid, self.model_pid):
                        kind = "driver" if process.pid == me.pid else "model"
                    else:
                        kind = known[0] if known else process_kind(process)
                    if kind in AGENT_BROWSER and os.sched_getscheduler(process.pid) == os.SCHED_IDLE:
                        kind = "judge"  # a browser that judges moves to the idle class after it starts
                    cpu[process.pid] = (kind, times.user + times.system)
            except (psutil.Error, ProcessLookupError):  # it ended meanwhile
                continue
        for pid, (kind, spent) in cpu.items():
            self._totals[kind] += max(spent - self._cpu.get(pid, (kind, 0.0))[1], 0.0)
        self._cpu = cpu
        return Sample(time.time(), dict(self._totals))
