"""Where the test suite's time goes: its wall time and CPU, the cores left idle, and by module.

    .venv/bin/python benchmarks/suite_time.py [--top 15] [-- PYTEST ARGS...]

Runs pytest as CI does (the pyproject's two processes, the whole suite unless PYTEST ARGS say
otherwise) with a probe plugin (``benchmarks/_suite_probe.py``) that notes when each test starts
and ends in each process, while this script samples the machine's CPU once a second. It prints
the run's wall time, the machine's CPU-seconds, how many cores were busy on average and how many
core-seconds stayed idle, then per module: its wall time, the cores the machine used while it
ran, and the idle core-seconds it accounts for (a share per module running then). The suite is
CPU-bound on 2 cores: its time is its CPU over 2, plus what waiting modules leave idle.

Two more figures say what the CPU is spent on and how fast the machine is:
- CPU-seconds by kind of process (Chromium renderers, Ray workers, the test processes...), from
  every process's CPU times read twice a second (a process's last half second before it exits
  is missed);
- a reference workload before the suite: a browser launch and three editor openings, in
  CPU-seconds per opening, so that runs on two machines (or one machine on two days) can be compared.

CPU is the machine's (``/proc/stat``), so run it on an otherwise quiet machine.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import subprocess
import sys
import tempfile
import threading
import time
from collections import Counter, defaultdict
from pathlib import Path

import psutil

from workers.editor import BrowserSession
from workers.editor._cache_template import TEMPLATE_ENV

REPO = Path(__file__).resolve().parents[1]
CORES = os.cpu_count() or 1


def busy_jiffies() -> int:
    """User, nice, system, irq and softirq time of every core, in clock ticks."""
    fields = Path("/proc/stat").read_text().splitlines()[0].split()
    return sum(int(fields[i]) for i in (1, 2, 3, 6, 7))


class CpuSampler(threading.Thread):
    """The machine's busy cores, once a second: ``(start, end, cores)`` per interval."""

    def __init__(self) -> None:
        super().__init__(daemon=True)
        self.intervals: list[tuple[float, float, float]] = []
        self.stop = threading.Event()
        self.ticks = os.sysconf("SC_CLK_TCK")

    def run(self) -> None:
        last_t, last_busy = time.time(), busy_jiffies()
        while not self.stop.wait(1.0):
            now, busy = time.time(), busy_jiffies()
            self.intervals.append((last_t, now, (busy - last_busy) / self.ticks / max(now - last_t, 1e-6)))
            last_t, last_busy = now, busy


KERNEL_THREADS = 2
"""The pid of kthreadd, the parent of every kernel thread (kdamond, which monitors memory, took 32 CPU-s
through one suite here: not the suite's, but the machine's)."""


class ProcessCpu(threading.Thread):
    """CPU-seconds of every process that ran meanwhile, summed by kind (``kind_of``)."""

    def __init__(self) -> None:
        super().__init__(daemon=True)
        self.stop = threading.Event()
        self._start: dict[tuple[int, float], float] = {}
        self._last: dict[tuple[int, float], tuple[str, float]] = {}

    def run(self) -> None:
        self._sample(first=True)
        while not self.stop.wait(0.5):
            self._sample(first=False)
        self._sample(first=False)

    def _sample(self, first: bool) -> None:
        for process in psutil.process_iter(["pid", "ppid", "name", "cmdline", "cpu_times", "create_time"]):
            info = process.info
            if info["cpu_times"] is None:
                continue
            key = (info["pid"], info["create_time"])
            spent = info["cpu_times"].user + info["cpu_times"].system
            name, cmdline = info["name"] or "", info["cmdline"] or []
            if key not in self._last:
                self._start[key] = spent if first else 0.0
                kernel = KERNEL_THREADS in (info["pid"], info["ppid"])
                kind = f"kernel {name}" if kernel else kind_of(cmdline, name)
            elif cmdline:  # read again: a process retitles itself after it starts (a Chromium renderer
                # forked from the zygote, a Ray worker once it runs an actor); an exiting one has none
                kind = kind_of(cmdline, name)
            else:
                kind = self._last[key][0]
            self._last[key] = (kind, spent)

    def by_kind(self) -> Counter[str]:
        spent: Counter[str] = Counter()
        for key, (kind, last) in self._last.items():
            spent[kind] += last - self._start[key]
        return spent


def kind_of(cmdline: list[str], name: str) -> str:
    """What a process is, for the CPU table: a Chromium process's type, a Ray process, a test process..."""
    line = " ".join(cmdline)
    if "chromium" in name or "/chromium" in line:
        kind = switch_value(cmdline, "--type", "browser")
        if "--top-chrome-webui" in cmdline:
            kind += " (browser UI)"
        if kind == "utility":
            kind += " " + switch_value(cmdline, "--utility-sub-type", "")
        return f"chromium {kind}"
    if line.startswith("ray::"):  # a Ray worker, titled by what it runs ("ray::JobWorker.run")
        return line.split()[0].split(".")[0]
    if "default_worker.py" in line:
        return "ray::IDLE"  # a Ray worker before it took a title
    if "gcs_server" in line or "raylet" in line or "site-packages/ray/" in line:
        return "ray services"
    if "playwright" in line and "node" in (name + line):
        return "playwright driver (node)"
    if "exec(eval(sys.stdin.readline()))" in line:
        return "pytest processes"
    if "scratchworld" in line:
        return "scratchworld commands"
    return "python, other" if "python" in name else "other"


def switch_value(cmdline: list[str], switch: str, default: str) -> str:
    """The value of a ``--switch=value`` argument, or ``default``."""
    return next((arg.split("=", 1)[1] for arg in cmdline if arg.startswith(f"{switch}=")), default)


def reference_opening_cpu(openings: int = 3) -> float:
    """Median CPU-seconds of the machine per editor opening (a browser started without a cache template, as
    before there were any, so that the figure compares with older runs; one editor at a time)."""

    async def measure() -> list[float]:
        spent = []
        async with BrowserSession() as session:
            for _ in range(openings):
                before = busy_jiffies()
                editor = await session.open_editor()
                spent.append((busy_jiffies() - before) / os.sysconf("SC_CLK_TCK"))
                await editor.close()
        return spent

    setting = os.environ.get(TEMPLATE_ENV)
    os.environ[TEMPLATE_ENV] = "off"
    try:
        return sorted(asyncio.run(measure()))[openings // 2]
    finally:
        if setting is None:
            del os.environ[TEMPLATE_ENV]
        else:
            os.environ[TEMPLATE_ENV] = setting


def read_tests(folder: Path) -> dict[str, list[tuple[float, float, str]]]:
    """Per test process: (start, end, node id) of each test, from the probe's files."""
    found: dict[str, list[tuple[float, float, str]]] = {}
    for path in sorted(folder.glob("*.tsv")):
        started: dict[str, float] = {}
        tests = []
        for line in path.read_text().splitlines():
            kind, at, node = line.split("\t", 2)
            if kind == "S":
                started[node] = float(at)
            elif node in started:
                tests.append((started.pop(node), float(at), node))
        found[path.stem] = tests
    return found


def overlap(a: float, b: float, start: float, end: float) -> float:
    """Seconds that the spans ``a..b`` and ``start..end`` share."""
    return max(0.0, min(b, end) - max(a, start))


def cores_between(intervals: list[tuple[float, float, float]], start: float, end: float) -> float:
    """Mean busy cores of the machine from ``start`` to ``end``."""
    used = sum(cores * overlap(a, b, start, end) for a, b, cores in intervals)
    return used / max(end - start, 1e-6)


def idle_by_module(
    intervals: list[tuple[float, float, float]], processes: dict[str, list[tuple[float, float, str]]]
) -> Counter[str]:
    """Idle core-seconds of each interval, shared among the modules running during it."""
    spans = [(s, e, node.split("::")[0]) for tests in processes.values() for s, e, node in tests]
    idle: Counter[str] = Counter()
    for a, b, cores in intervals:
        running = [(module, overlap(a, b, s, e)) for s, e, module in spans if overlap(a, b, s, e) > 0]
        total = sum(part for _, part in running)
        for module, part in running:
            idle[module] += max(0.0, CORES - cores) * (b - a) * part / total
    return idle


def report(
    intervals: list[tuple[float, float, float]],
    processes: dict[str, list[tuple[float, float, str]]],
    by_kind: Counter[str],
    top: int,
) -> None:
    wall = intervals[-1][1] - intervals[0][0] if intervals else 0.0
    cpu = sum(cores * (b - a) for a, b, cores in intervals)
    print(f"\nwall {wall:.0f} s, CPU {cpu:.0f} CPU-s, {cpu / max(wall, 1e-6):.2f} of {CORES} cores busy on average")
    print(f"idle: {CORES * wall - cpu:.0f} core-s ({100 * (1 - cpu / max(CORES * wall, 1e-6)):.0f}%)")
    for name, tests in sorted(processes.items()):
        if tests:
            print(f"process {name}: {len(tests)} tests, {tests[-1][1] - tests[0][0]:.0f} s from first to last")
    modules: dict[str, list[float]] = defaultdict(lambda: [float("inf"), 0.0, 0.0])
    for tests in processes.values():
        for start, end, node in tests:
            span = modules[node.split("::")[0]]
            span[0], span[1], span[2] = min(span[0], start), max(span[1], end), span[2] + end - start
    idle = idle_by_module(intervals, processes)
    rows = sorted(modules.items(), key=lambda item: -item[1][2])[:top]
    print(f"\n{'module':<44} {'wall s':>7} {'cores':>6} {'idle core-s':>12}")
    for module, (start, end, spent) in rows:
        print(f"{module:<44} {spent:7.0f} {cores_between(intervals, start, end):6.2f} {idle[module]:12.0f}")
    print(f"\nidlest modules (idle core-s they account for), top {top}:")
    for module, value in idle.most_common(top):
        print(f"  {value:6.0f}  {module}")
    print(f"\nCPU-s by kind of process (all processes: {sum(by_kind.values()):.0f}):")
    for kind, value in by_kind.most_common(top):
        print(f"  {value:7.0f}  {kind}")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--top", type=int, default=15, help="modules listed per table")
    parser.add_argument("pytest_args", nargs="*", help="after --: arguments for pytest (default: the whole suite)")
    args = parser.parse_args()
    print(f"reference: an editor opening costs {reference_opening_cpu():.2f} CPU-s on this machine", flush=True)
    with tempfile.TemporaryDirectory(prefix="suite-time-") as folder:
        env = {
            **os.environ,
            "SUITE_PROBE_DIR": folder,
            "PYTHONPATH": os.pathsep.join(filter(None, [str(REPO / "benchmarks"), os.environ.get("PYTHONPATH")])),
        }
        sampler, kinds = CpuSampler(), ProcessCpu()
        sampler.start()
        kinds.start()
        done = subprocess.run(
            [sys.executable, "-m", "pytest", "-q", "-p", "_suite_probe", "-p", "no:cacheprovider", *args.pytest_args],
            cwd=REPO,
            env=env,
            check=False,
        )
        for thread in (sampler, kinds):
            thread.stop.set()
            thread.join()
        report(sampler.intervals, read_tests(Path(folder)), kinds.by_kind(), args.top)
    return done.returncode


if __name__ == "__main__":
    sys.exit(main())
