"""Prints how many LLM episodes one node holds at once, and what each costs it while it waits on its model.

    .venv/bin/python benchmarks/density.py [--n 1,8,16,32,48] [--delay 5] [--steps 6] [--clock virtual,real]

For each episode clock and each N, one real sweep of N jobs (tasks x seeds of our suite) of the
``llm`` agent in composite mode runs on a private local Ray with two workers (one Chromium each)
holding N/2 pages (N = 1: one worker, one page, and 4 jobs one after the other, so that its
baseline has more than one episode's steps), so that all N episodes are in flight at once. The
model is ``tests/support/openai_server.py`` answering every request exactly ``--delay`` seconds after it
arrived with a valid ``add_block`` (a "when green flag clicked" hat), so every episode runs
``--steps`` steps and stops at the step limit (outcome ``failed``, never ``error``). While a sweep
runs, a thread reads every 0.5 s the CPU seconds of each Chromium process descending from this
process: a private Ray's raylet is a child of the driver that started it and its workers are the
raylet's children, so these are exactly the workers' browsers (nothing else here starts one). The
server's record of arrivals tells how many requests wait at any instant; the run directory's
Parquet gives each episode's start, set-up, agent loop and end, its worker's memory, and each
step's latency.

- in flight max/med: episodes in their agent loop (set-up done, evaluation not begun: those that
  can wait on the model) at each sample of the steady phase, from the first agent loop's start to
  the last one's end (the set-up ramp comes before it, evaluations after);
- CPU/wait: the browsers' CPU (cores, from per-process CPU-second deltas) over the sample
  intervals in which every episode in flight (start to end: set-up and evaluation count as not
  waiting) waited on the model from one end of the interval to the other, per episode waiting:
  CPU seconds summed over those intervals / waiting episode-seconds in them. The browsers' own
  processes and pooled idle editors are included. ``(k)``: how many intervals qualified (few when
  many episodes interleave their steps; ``-``: none). ``fit``: the same from every interval, by
  least squares of the browsers' cores on the episodes waiting and the episodes busy in it (plus a
  fixed part for the browsers themselves): what one more waiting page adds;
- PSS/editor: every result carries its worker's browser PSS (all its Chromium processes: browser,
  GPU, utilities, renderers; an editor has several renderer processes, so those do not count
  editors) and the editors its pool held (lent or pooled); per worker its result with the most
  editors, summed over workers: PSS / editors. Each browser's fixed processes (~250 MB) are shared
  by its editors, so this falls as N grows;
- overhead p50/p95: per step, ``latency_s`` (observation + model call + action) minus
  ``delay x llm_calls``: what the harness adds to the model's own time. The first model call of a
  worker also imports LiteLLM (4-9 s here, more under load), which shows in p95;
- ep/h: the jobs over the run phase, the first episode's start to the last one's end (Ray, worker and
  browser start-up excluded); start s: from the sweep's start to its first episode's (Ray and the
  workers start, and each worker opens the editors its episodes will use); errors: jobs whose
  outcome is ``error`` (must be 0).

Targets (issue 16): at N = 32 the step overhead p50 within 2x of N = 1 and no error, on each
clock; a waiting page costs at most 0.05 of a core on the virtual clock (checked at the largest N
with at least 3 qualifying intervals, where the browsers' fixed costs are shared the most).
"""

from __future__ import annotations

import argparse
import itertools
import math
import os
import statistics
import sys
import tempfile
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # for tests.support.openai_server, the tests' model server

import numpy as np
import psutil
from rich.console import Console

from scratchworld_dist._run import run_sweep
from scratchworld_dist.results import RunStore
from scratchworld_dist.suites import load_suite
from scratchworld_dist.sweep import SweepConfig
from tests.support.openai_server import Behaviour, OpenAIServer

REPO = Path(__file__).resolve().parents[1]
TASKS = [task.id for task in load_suite(REPO / "tasks").tasks]
INTERVAL_S = 0.5
KEY_ENV = "SCRATCHWORLD_DENSITY_API_KEY"
REPLY = 'Analysis: a harmless edit.\n```json\n{"api": "add_block", "args": {"blockType": "event_whenflagclicked"}}\n```'


class DelayedModel:
    """The server's responder: every request is answered ``delay`` seconds after it arrived; arrivals are kept."""

    def __init__(self, delay: float) -> None:
        self.delay = delay
        self.arrivals: list[float] = []
        self._lock = threading.Lock()

    def __call__(self, body: dict[str, Any]) -> Behaviour:
        with self._lock:
            self.arrivals.append(time.time())
        return Behaviour("hang", text=REPLY, seconds=self.delay, prompt_tokens=2000, completion_tokens=40)

    def waiting(self) -> list[tuple[float, float]]:
        """(arrival, answer) of every request so far: it waits on the model in between."""
        with self._lock:
            return [(t, t + self.delay) for t in self.arrivals]


@dataclass(frozen=True)
class Sample:
    t: float
    cpu_s: float
    """CPU seconds the browsers spent since sampling began (per process, so exits lose no earlier CPU)."""


@dataclass
class Sampler:
    """Samples the Chromium processes below this process every ``INTERVAL_S`` in a thread."""

    samples: list[Sample] = field(default_factory=list)
    _stop: threading.Event = field(default_factory=threading.Event)
    _cpu: dict[int, float] = field(default_factory=dict)
    _total: float = 0.0

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
        cpu: dict[int, float] = {}
        for process in psutil.Process().children(recursive=True):
            try:
                with process.oneshot():
                    if "chrom" in process.name():
                        times = process.cpu_times()
                        cpu[process.pid] = times.user + times.system
            except psutil.Error:  # it ended meanwhile
                continue
        self._total += sum(max(spent - self._cpu.get(pid, 0.0), 0.0) for pid, spent in cpu.items())
        self._cpu = cpu
        return Sample(time.time(), self._total)


@dataclass(frozen=True)
class Row:
    clock: str
    n: int
    in_flight: tuple[int, float]
    cpu_per_wait: float | None
    cpu_intervals: int
    cpu_per_wait_fit: float | None
    pss_per_editor: float | None
    overhead: tuple[float, float]
    per_hour: float
    start_s: float
    errors: int
    problems: list[str]


MIN_JOBS = 4
"""Jobs of a sweep at least: at N = 1 they run one after the other, so the baseline has 4 episodes' steps."""


def job_count(n: int) -> int:
    return max(n, MIN_JOBS)


def config(n: int, clock: str, steps: int, url: str, out: Path) -> SweepConfig:
    workers = 1 if n == 1 else 2
    pages = math.ceil(n / workers)
    jobs = job_count(n)
    tasks = max(k for k in range(1, min(jobs, len(TASKS)) + 1) if jobs % k == 0)  # tasks x seeds = jobs exactly
    model = {"model": "openai/gpt-4o-mini", "name": "density", "temperature": 0, "api_base": url}
    limits = {"browser_slots": workers * pages, "pages_per_worker": pages, "episode_timeout_s": 3600, "retries": 0}
    return SweepConfig.model_validate(
        {
            "name": f"density-{clock}-{n}",
            "suite": REPO / "tasks",
            "tasks": {"ids": TASKS[:tasks]},
            "agent": "llm",
            "models": [{**model, "api_key_env": KEY_ENV}],
            "seeds": jobs // tasks,
            "episodes": {"modes": ["composite"], "max_steps": steps, "episode_clock": clock},
            "limits": limits,
            "output": out,
        }
    )


def overlap(spans: list[tuple[float, float]], t0: float, t1: float) -> float:
    """Seconds of the spans inside [t0, t1], summed (episode-seconds when each span is one episode's)."""
    return sum(max(0.0, min(end, t1) - max(start, t0)) for start, end in spans)


def marginal_waiting_cpu(rates: list[tuple[float, float, float]]) -> float | None:
    """Least squares over every interval: cores = fixed + a x episodes waiting + b x episodes busy; returns a.

    Uses all intervals, also when episodes interleave their steps so that none is all-waiting."""
    if len(rates) < 10:
        return None
    table = np.array(rates)
    design = np.column_stack([np.ones(len(table)), table[:, 0], table[:, 1]])
    if np.linalg.matrix_rank(design) < 3:
        return None
    coefficients, *_ = np.linalg.lstsq(design, table[:, 2], rcond=None)
    return float(coefficients[1])


def measure(n: int, clock: str, args: argparse.Namespace, server: OpenAIServer, model: DelayedModel) -> Row:
    with tempfile.TemporaryDirectory(prefix="density-") as tmp:
        out = args.keep / f"{clock}-{n}" if args.keep else Path(tmp) / "run"
        sweep = config(n, clock, args.steps, server.url, out)
        already = len(model.waiting())
        began = time.time()
        with Sampler() as sampler:
            run_sweep(sweep, console=Console(quiet=True))
        store = RunStore(sweep.run_dir())
        jobs = store.read_table("jobs").to_pylist()
        steps = store.read_table("steps").to_pylist()
    requests = model.waiting()[already:]
    episodes = [(j["started_at"].timestamp(), j["finished_at"].timestamp()) for j in jobs]
    loops = [(s + j["setup_s"], s + j["setup_s"] + j["agent_s"]) for j, (s, _) in zip(jobs, episodes, strict=True)]
    first, last = min(s for s, _ in episodes), max(e for _, e in episodes)
    run = [s for s in sampler.samples if first <= s.t <= last]
    lo, hi = min(a for a, _ in loops), max(b for _, b in loops)
    counts = [sum(1 for a, b in loops if a <= s.t < b) for s in run if lo <= s.t <= hi] or [0]

    cpu = waited = 0.0
    intervals = 0
    rates: list[tuple[float, float, float]] = []  # per interval: episodes waiting, episodes busy, cores
    for before, after in itertools.pairwise(run):
        waiting = overlap(requests, before.t, after.t)
        busy = overlap(episodes, before.t, after.t) - waiting  # in flight but not waiting on the model
        span = after.t - before.t
        rates.append((waiting / span, busy / span, (after.cpu_s - before.cpu_s) / span))
        if waiting > 0 and busy < 0.01:
            cpu, waited, intervals = cpu + after.cpu_s - before.cpu_s, waited + waiting, intervals + 1
    fullest: dict[Any, dict[str, Any]] = {}  # per worker, the row of its fullest moment
    for j in jobs:
        key = (j["worker_host"], j["worker_pid"])
        if j["editors_held"] and j["editors_held"] >= fullest.get(key, {}).get("editors_held", 0):
            fullest[key] = j
    held = sum(j["editors_held"] for j in fullest.values())
    overheads = [s["latency_s"] - args.delay * s["llm_calls"] for s in steps] or [math.nan]

    problems = []
    if len(jobs) != job_count(n):
        problems.append(f"{len(jobs)} job row(s) for {job_count(n)} job(s)")
    short = sum(1 for j in jobs if j["steps"] != args.steps)
    if short:
        problems.append(f"{short} job(s) did not run exactly {args.steps} steps")
    refused = sum(1 for s in steps if not s["ok"])
    if refused:
        problems.append(f"{refused} step(s) failed, e.g. {next(s['error_message'] for s in steps if not s['ok'])}")
    return Row(
        clock=clock,
        n=n,
        in_flight=(max(counts), statistics.median(counts)),
        cpu_per_wait=cpu / waited if waited else None,
        cpu_intervals=intervals,
        cpu_per_wait_fit=marginal_waiting_cpu(rates),
        pss_per_editor=sum(j["browser_pss_mb"] for j in fullest.values()) / held if held else None,
        overhead=(float(np.percentile(overheads, 50)), float(np.percentile(overheads, 95))),
        per_hour=len(jobs) / (last - first) * 3600,
        start_s=first - began,
        errors=sum(1 for j in jobs if j["outcome"] == "error"),
        problems=problems,
    )


HEADER = (
    f"{'clock':<8} {'N':>3}  {'in flight max/med':>17}  {'CPU/wait (cores)':>16}  {'fit':>6}  {'PSS/editor MB':>13}  "
    f"{'overhead p50/p95 s':>18}  {'ep/h':>6}  {'start s':>7}  {'errors':>6}"
)


def line(row: Row) -> str:
    flight = f"{row.in_flight[0]}/{row.in_flight[1]:g}"
    cpu = f"{row.cpu_per_wait:.3f} ({row.cpu_intervals})" if row.cpu_per_wait is not None else "-"
    pss = f"{row.pss_per_editor:.0f}" if row.pss_per_editor is not None else "-"
    fit = f"{row.cpu_per_wait_fit:.3f}" if row.cpu_per_wait_fit is not None else "-"
    overhead = f"{row.overhead[0]:.2f}/{row.overhead[1]:.2f}"
    return (
        f"{row.clock:<8} {row.n:>3}  {flight:>17}  {cpu:>16}  {fit:>6}  {pss:>13}  {overhead:>18}  "
        f"{row.per_hour:>6.0f}  {row.start_s:>7.0f}  {row.errors:>6}"
    )


def cpu_verdict(label: str, rows: list[Row], cores_of: Callable[[Row], float | None]) -> str:
    """The virtual-clock target, checked at the largest N that has the figure."""
    measured = [(row.n, cores) for row in rows if (cores := cores_of(row)) is not None]
    if not measured:
        return f"virtual: {label}: not measured"
    n, cores = max(measured)
    return f"virtual: {label} {cores:.3f} core(s) at N={n} <= 0.05: {'met' if cores <= 0.05 else 'NOT met'}"


def targets(rows: list[Row]) -> list[str]:
    verdicts = []
    for clock in dict.fromkeys(row.clock for row in rows):
        by_n = {row.n: row for row in rows if row.clock == clock}
        if 1 in by_n and 32 in by_n:
            base, dense = by_n[1].overhead[0], by_n[32].overhead[0]
            met = dense <= 2 * base and by_n[32].errors == 0
            verdicts.append(
                f"{clock}: N=32 step overhead p50 {dense:.2f} s vs 2 x {base:.2f} s at N=1, "
                f"{by_n[32].errors} error(s): {'met' if met else 'NOT met'}"
            )
        else:
            verdicts.append(f"{clock}: N=32 vs N=1 overhead: not measured (needs --n with 1 and 32)")
        if clock == "virtual":
            rows_here = list(by_n.values())
            verdicts.append(
                cpu_verdict(
                    "CPU per waiting page (all-waiting intervals)",
                    rows_here,
                    lambda r: r.cpu_per_wait if r.cpu_intervals >= 3 else None,
                )
            )
            fit = cpu_verdict("CPU one more waiting page adds (fit)", rows_here, lambda r: r.cpu_per_wait_fit)
            verdicts.append(fit)
    return verdicts


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", default="1,8,16,32,48", help="episodes in flight, comma-separated")
    parser.add_argument("--delay", type=float, default=5.0, help="seconds the model takes to answer")
    parser.add_argument("--steps", type=int, default=6, help="steps per episode (max_steps)")
    parser.add_argument("--clock", default="virtual,real", help="episode clocks, comma-separated")
    parser.add_argument("--keep", type=Path, help="keep each sweep's run directory under this one")
    args = parser.parse_args()
    counts = [int(n) for n in args.n.split(",")]
    clocks = args.clock.split(",")
    os.environ[KEY_ENV] = "sk-density-benchmark"  # the workers of the private Ray inherit it
    rows: list[Row] = []
    model = DelayedModel(args.delay)
    with OpenAIServer(responder=model) as server:
        for clock in clocks:
            for n in counts:
                started = time.perf_counter()
                rows.append(measure(n, clock, args, server, model))
                print(f"{clock} N={n}: sweep took {time.perf_counter() - started:.0f} s", file=sys.stderr)
    print(f"{args.steps} steps per episode, model answering after {args.delay:g} s, {os.cpu_count()} core(s)")
    print(HEADER)
    for row in rows:
        print(line(row))
        for problem in row.problems:
            print(f"  {row.clock} N={row.n}: {problem}")
    print("targets:")
    for verdict in targets(rows):
        print(f"  {verdict}")


if __name__ == "__main__":
    main()
