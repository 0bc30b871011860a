"""Prints how many LLM episodes one node holds at once, and what each costs it while it waits on its model.

    .venv/bin/python benchmarks/density.py [--n 1,8,16,32,48] [--delay 5] [--steps 6] [--clock virtual,real]
        [--mode composite,primitive] [--repeat 3]

For each episode clock and each N, one real sweep of N jobs (tasks x seeds of our suite) of the
``llm`` agent in each ``--mode`` runs on a private local Ray with two workers (one Chromium each)
holding N/2 pages (N = 1: one worker, one page, and 4 jobs one after the other, so that its
baseline has more than one episode's steps), so that all N episodes are in flight at once. The
model is ``tests/support/openai_server.py``, in a process of its own (``benchmarks/_delayed_model.py``),
answering every request exactly ``--delay`` seconds after it
arrived with a valid action (composite: ``add_block``, a "when green flag clicked" hat; primitive: a
``drag_and_drop`` from the palette into the code area, so every step observes with a screenshot, the element
list and OCR where the DOM has no text, and moves the mouse through half a second of frames), so every episode runs
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
  ``delay x llm_calls``: what the harness adds to the model's own time; ``steady``: the same over the
  steps that are neither an episode's first nor its last (those share the CPU with episodes starting
  and ending, and with evaluations; ``start``/``end`` p95 are printed apart); ``obs p50/p95``: the
  observation's own seconds (``observation_s``), which in primitive mode are the screenshot, the
  element list and OCR;
- where the cores went, per phase: ``start`` (the sweep's start until its first episode's: Ray, the workers and
  their browsers start and open their editors ahead; the first sample's interval is left out), then of the run:
  ``ramp`` (episodes starting, until 90% of the most are in their
  agent loop), ``full`` (at least 90% of the most in their loop: the load the targets are about) and ``end``
  (from the first episode's end: episodes end, save and recycle their pages, and are judged beside those still
  acting); per phase its seconds, its steps' overhead p50/p95, the model calls per second, and the cores of each
  kind of process below this one (``PROCESS_KINDS``: the agents' Chromium processes by type, the idle-class
  browsers that judge, Playwright's drivers, Ray's workers, this process, the model server's, Ray's own),
  with the CPU-ms per model call in brackets;
- the model server's lag: per reply, the seconds from its due time (arrival + ``--delay``) to its write, p50/p95,
  by the server's own clock: a late server would otherwise count as the harness's overhead;
- ep/h: the jobs over the run phase, the first episode's start to the last one's end (Ray, worker and
  browser start-up excluded); start s: from the sweep's start to its first episode's (Ray and the
  workers start, and each worker opens the editors its episodes will use); all in: from the sweep's
  start to the first moment N episodes were in flight at once ("-": never); errors: jobs whose
  outcome is ``error`` (must be 0).

Targets (issues 16 and 56): at every N above 1 the step overhead p50 within 2x of N = 1, the steady
steps' p95 under 1 s (composite; primitive's is reported, issue 56 sets it no line), and no error, on each
clock and mode (``--repeat`` runs each N that many times
in a row: each run is checked); a waiting page costs at most 0.05 of a core on the virtual clock
(checked at the largest N with at least 3 qualifying intervals, where the browsers' fixed costs are
shared the most).
"""

from __future__ import annotations

import argparse
import itertools
import math
import os
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # for tests.support.openai_server, the tests' model server

import numpy as np
from _delayed_model import REPLIES, DelayedModel
from _process_sampler import PROCESS_KINDS, Sample, Sampler
from rich.console import Console

from scratchworld_dist._run import run_sweep
from scratchworld_dist.results import RunStore
from scratchworld_dist.suites import load_suite
from scratchworld_dist.sweep import SweepConfig
from workers.editor import EditorAssets
from workers.editor._cache_template import CacheTemplate
from workers.node import default_chromium

REPO = Path(__file__).resolve().parents[1]
TASKS = [task.id for task in load_suite(REPO / "tasks").tasks]
KEY_ENV = "SCRATCHWORLD_DENSITY_API_KEY"


@dataclass(frozen=True)
class Row:
    clock: str
    mode: str
    n: int
    in_flight: tuple[int, float]
    cpu_per_wait: float | None
    cpu_intervals: int
    cpu_per_wait_fit: float | None
    pss_per_editor: float | None
    overhead: tuple[float, float]
    steady: tuple[float, float]
    """Overhead p50/p95 of the steps that are neither an episode's first nor its last."""
    start_end_p95: tuple[float, float]
    """Overhead p95 of episodes' first steps and of their last steps."""
    observation: tuple[float, float]
    per_hour: float
    start_s: float
    all_in_s: float | None
    """From the sweep's start to the first moment N episodes were in flight at once (None: never)."""
    errors: int
    problems: list[str]
    phases: list[Phase]
    """Where the cores went while episodes started, while the node was fullest, and while they ended."""
    model_late: tuple[float, float]
    """p50/p95 of the model server's replies past their due time, by its own clock (its lag, not the harness's)."""


@dataclass(frozen=True)
class Phase:
    """Where the cores went in one phase of the run phase: ``ramp`` (episodes starting until 90% of the most are
    in their agent loop), ``full`` (at least 90% of the most in their loop) and ``end`` (from the first
    episode's end: episodes end, save and recycle their pages, and are judged, beside those still acting)."""

    name: str
    seconds: float
    requests_per_s: float
    cores: dict[str, float]
    """Cores per ``PROCESS_KINDS`` entry over the phase's sample intervals."""
    overhead: tuple[float, float]
    """Step overhead p50/p95 of the steps that began in the phase."""

    def line(self) -> str:
        per_call = (
            {kind: cores / self.requests_per_s for kind, cores in self.cores.items()} if self.requests_per_s else {}
        )
        kinds = "  ".join(
            f"{kind} {cores:.2f}" + (f" ({per_call[kind] * 1000:.0f})" if per_call else "")
            for kind, cores in self.cores.items()
        )
        return (
            f"{self.name:<4} {self.seconds:4.0f} s, overhead {pair(self.overhead)} s, {self.requests_per_s:4.1f} "
            f"model calls/s, {sum(self.cores.values()):.2f} cores: {kinds}"
        )


MIN_JOBS = 4
"""Jobs of a sweep at least: at N = 1 they run one after the other, so the baseline has 4 episodes' steps."""


def job_count(n: int) -> int:
    return max(n, MIN_JOBS)


def config(n: int, clock: str, mode: str, steps: int, url: str, out: Path) -> SweepConfig:
    workers = 1 if n == 1 else 2
    pages = math.ceil(n / workers)
    jobs = job_count(n)
    tasks = max(k for k in range(1, min(jobs, len(TASKS)) + 1) if jobs % k == 0)  # tasks x seeds = jobs exactly
    model = {"model": "openai/gpt-4o-mini", "name": "density", "temperature": 0, "api_base": url}
    limits = {"browser_slots": workers * pages, "pages_per_worker": pages, "episode_timeout_s": 3600, "retries": 0}
    return SweepConfig.model_validate(
        {
            "name": f"density-{mode}-{clock}-{n}",
            "suite": REPO / "tasks",
            "tasks": {"ids": TASKS[:tasks]},
            "agent": "llm",
            "models": [{**model, "api_key_env": KEY_ENV}],
            "seeds": jobs // tasks,
            "episodes": {"modes": [mode], "max_steps": steps, "episode_clock": clock},
            "limits": limits,
            "output": out,
        }
    )


def step_starts(
    jobs: list[dict[str, Any]], steps: list[dict[str, Any]], overhead: Callable[[dict[str, Any]], float]
) -> list[tuple[float, float]]:
    """(start, overhead) of every step: an episode's steps follow one another from its agent loop's start."""
    by_job: dict[str, list[dict[str, Any]]] = {}
    for step in steps:
        by_job.setdefault(step["job_id"], []).append(step)
    found = []
    for job in jobs:
        at = job["started_at"].timestamp() + job["setup_s"]
        for step in sorted(by_job.get(job["job_id"], []), key=lambda s: s["step"]):
            found.append((at, overhead(step)))
            at += step["latency_s"]
    return found


def first_all_in_flight(episodes: list[tuple[float, float]], n: int) -> float | None:
    """The first moment ``n`` of the (start, end) ``episodes`` were in flight at once (an end before a start
    at the same moment), or None."""
    in_flight = 0
    for moment, change in sorted([(start, 1) for start, _ in episodes] + [(end, -1) for _, end in episodes]):
        in_flight += change
        if in_flight >= n:
            return moment
    return None


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


def percentiles(values: list[float]) -> tuple[float, float]:
    """p50 and p95 (NaN for no values)."""
    if not values:
        return math.nan, math.nan
    return float(np.percentile(values, 50)), float(np.percentile(values, 95))


def measure(n: int, clock: str, mode: str, run: int, args: argparse.Namespace, model: DelayedModel) -> Row:
    with tempfile.TemporaryDirectory(prefix="density-") as tmp:
        out = args.keep / f"{mode}-{clock}-{n}-{run}" if args.keep else Path(tmp) / "run"
        sweep = config(n, clock, mode, args.steps, model.url, out)
        model.set_reply(mode)
        earlier = model.served()
        began = time.time()
        with Sampler(model_pid=model.pid) as sampler:
            run_sweep(sweep, console=Console(quiet=True))
        store = RunStore(sweep.run_dir())
        jobs = store.read_table("jobs").to_pylist()
        steps = store.read_table("steps").to_pylist()
    served = model.served()
    requests = served.waiting[len(earlier.waiting) :]
    episodes = [(j["started_at"].timestamp(), j["finished_at"].timestamp()) for j in jobs]
    loops = [(s + j["setup_s"], s + j["setup_s"] + j["agent_s"]) for j, (s, _) in zip(jobs, episodes, strict=True)]
    first, last = min(s for s, _ in episodes), max(e for _, e in episodes)
    run = [s for s in sampler.samples if first <= s.t <= last]
    lo, hi = min(a for a, _ in loops), max(b for _, b in loops)
    in_loop = [sum(1 for a, b in loops if a <= s.t < b) for s in run]  # per sample: episodes in their agent loop
    counts = [k for s, k in zip(run, in_loop, strict=True) if lo <= s.t <= hi] or [0]

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

    def overhead(step: dict[str, Any]) -> float:
        return float(step["latency_s"] - args.delay * step["llm_calls"])

    last_step = {j["job_id"]: j["steps"] - 1 for j in jobs}
    overheads = [overhead(s) for s in steps] or [math.nan]
    firsts = [overhead(s) for s in steps if s["step"] == 0]
    lasts = [overhead(s) for s in steps if s["step"] == last_step.get(s["job_id"]) and s["step"] > 0]
    steady = [overhead(s) for s in steps if 0 < s["step"] < last_step.get(s["job_id"], 0)]

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
        mode=mode,
        n=n,
        in_flight=(max(counts), statistics.median(counts)),
        cpu_per_wait=cpu / waited if waited else None,
        cpu_intervals=intervals,
        cpu_per_wait_fit=marginal_waiting_cpu(rates),
        pss_per_editor=sum(j["browser_pss_mb"] for j in fullest.values()) / held if held else None,
        overhead=percentiles(overheads),
        steady=percentiles(steady),
        start_end_p95=(percentiles(firsts)[1], percentiles(lasts)[1]),
        observation=percentiles([s["observation_s"] for s in steps if s["observation_s"] is not None]),
        per_hour=len(jobs) / (last - first) * 3600,
        start_s=first - began,
        all_in_s=None if (all_in := first_all_in_flight(episodes, n)) is None else all_in - began,
        errors=sum(1 for j in jobs if j["outcome"] == "error"),
        problems=problems,
        phases=[
            *start_phase([s for s in sampler.samples if s.t <= first]),
            *phases(run, in_loop, loops, requests, step_starts(jobs, steps, overhead)),
        ],
        model_late=percentiles(served.lateness[len(earlier.lateness) :]),
    )


def start_phase(samples: list[Sample]) -> list[Phase]:
    """The sweep's start, from the first sample to the first episode's start: Ray and the workers start, the
    workers open their editors ahead (and import LiteLLM meanwhile). No model call falls in it."""
    seconds = samples[-1].t - samples[0].t if len(samples) > 1 else 0.0
    if seconds <= 0:
        return []
    cores = {kind: (samples[-1].by_kind[kind] - samples[0].by_kind[kind]) / seconds for kind in PROCESS_KINDS}
    return [Phase("start", seconds, 0.0, cores, (math.nan, math.nan))]


def phases(
    run: list[Sample],
    in_loop: list[int],
    loops: list[tuple[float, float]],
    requests: list[tuple[float, float]],
    step_overheads: list[tuple[float, float]],
) -> list[Phase]:
    """The run phase's ramp, full and end (see ``Phase``); ``in_loop``: the episodes in their agent loop at each
    sample of ``run``; ``step_overheads``: (start, overhead) of every step."""
    if not in_loop or max(in_loop) == 0:
        return []
    floor = 0.9 * max(in_loop)
    first_end = min(b for _, b in loops)
    full_at = next(s.t for s, k in zip(run, in_loop, strict=True) if k >= floor)

    def kind_of(sample: Sample, k: int) -> str:
        if sample.t >= first_end:
            return "end"
        return "full" if k >= floor and sample.t >= full_at else "ramp"

    found = []
    for name in ("ramp", "full", "end"):
        spans = [
            (before, after)
            for (before, after), k in zip(itertools.pairwise(run), in_loop, strict=False)
            if kind_of(before, k) == name
        ]
        seconds = sum(after.t - before.t for before, after in spans)
        if seconds <= 0:
            continue
        cores = {kind: sum(a.by_kind[kind] - b.by_kind[kind] for b, a in spans) / seconds for kind in PROCESS_KINDS}
        calls = sum(1 for arrival, _ in requests for b, a in spans if b.t <= arrival < a.t)
        overheads = [o for t, o in step_overheads for b, a in spans if b.t <= t < a.t]
        found.append(Phase(name, seconds, calls / seconds, cores, percentiles(overheads)))
    return found


HEADER = (
    f"{'mode':<9} {'clock':<7} {'N':>3}  {'in flight':>9}  {'CPU/wait':>11}  {'fit':>6}  {'PSS/ed':>6}  "
    f"{'overhead':>9}  {'steady':>9}  {'1st/last p95':>12}  {'obs p50/p95':>11}  {'ep/h':>5}  {'start':>5}  "
    f"{'all in':>6}  {'err':>3}"
)
"""Columns: in flight max/median; CPU/wait in cores (qualifying intervals); PSS per editor in MB; overhead and
steady in s, p50/p95; the first and last steps' overhead p95 in s; the observation's s; start and all in, in s."""


def pair(values: tuple[float, float], digits: int = 2) -> str:
    return f"{values[0]:.{digits}f}/{values[1]:.{digits}f}"


def line(row: Row) -> str:
    flight = f"{row.in_flight[0]}/{row.in_flight[1]:g}"
    cpu = f"{row.cpu_per_wait:.3f} ({row.cpu_intervals})" if row.cpu_per_wait is not None else "-"
    pss = f"{row.pss_per_editor:.0f}" if row.pss_per_editor is not None else "-"
    fit = f"{row.cpu_per_wait_fit:.3f}" if row.cpu_per_wait_fit is not None else "-"
    all_in = f"{row.all_in_s:.0f}" if row.all_in_s is not None else "-"
    return (
        f"{row.mode:<9} {row.clock:<7} {row.n:>3}  {flight:>9}  {cpu:>11}  {fit:>6}  {pss:>6}  "
        f"{pair(row.overhead):>9}  {pair(row.steady):>9}  {pair(row.start_end_p95, 1):>12}  "
        f"{pair(row.observation):>11}  {row.per_hour:>5.0f}  {row.start_s:>5.0f}  {all_in:>6}  {row.errors:>3}"
    )


def cpu_verdict(label: str, rows: list[Row], cores_of: Callable[[Row], float | None]) -> str:
    """The virtual-clock target, checked at the largest N that has the figure."""
    measured = [(row.n, cores) for row in rows if (cores := cores_of(row)) is not None]
    if not measured:
        return f"virtual: {label}: not measured"
    n, cores = max(measured)
    return f"virtual: {label} {cores:.3f} core(s) at N={n} <= 0.05: {'met' if cores <= 0.05 else 'NOT met'}"


def density_verdicts(rows: list[Row]) -> list[str]:
    """Per clock and mode, every run at N > 1 against N = 1's overhead p50 (the median of its runs)."""
    verdicts = []
    for clock, mode in dict.fromkeys((row.clock, row.mode) for row in rows):
        here = [row for row in rows if (row.clock, row.mode) == (clock, mode)]
        bases = [row.overhead[0] for row in here if row.n == 1]
        if not bases:
            verdicts.append(f"{mode} {clock}: not measured against N=1 (needs --n with 1)")
            continue
        base = statistics.median(bases)
        for row in (row for row in here if row.n > 1):
            steady_line = mode != "primitive"
            met = (
                row.overhead[0] <= 2 * base
                and (row.steady[1] < 1.0 or not steady_line)
                and row.errors == 0
                and not row.problems
            )
            steady = f"steady p95 {row.steady[1]:.2f} s" + (" < 1 s" if steady_line else " (reported)")
            verdicts.append(
                f"{mode} {clock} N={row.n}: overhead p50 {row.overhead[0]:.2f} s vs 2 x {base:.2f} s at N=1, "
                f"{steady}, {row.errors} error(s): {'met' if met else 'NOT met'}"
            )
    return verdicts


def targets(rows: list[Row]) -> list[str]:
    verdicts = density_verdicts(rows)
    waiting = [row for row in rows if row.clock == "virtual" and row.mode == "composite"]
    if waiting:
        verdicts.append(
            cpu_verdict(
                "CPU per waiting page (all-waiting intervals)",
                waiting,
                lambda r: r.cpu_per_wait if r.cpu_intervals >= 3 else None,
            )
        )
        verdicts.append(cpu_verdict("CPU one more waiting page adds (fit)", waiting, lambda r: r.cpu_per_wait_fit))
    return verdicts


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", default="1,8,16,32,48", help="episodes in flight, comma-separated")
    parser.add_argument("--delay", type=float, default=5.0, help="seconds the model takes to answer")
    parser.add_argument("--steps", type=int, default=6, help="steps per episode (max_steps)")
    parser.add_argument("--clock", default="virtual,real", help="episode clocks, comma-separated")
    parser.add_argument("--mode", default="composite", help="episode modes, comma-separated (composite, primitive)")
    parser.add_argument("--repeat", type=int, default=1, help="runs of each N, one after the other")
    parser.add_argument("--keep", type=Path, help="keep each sweep's run directory under this one")
    args = parser.parse_args()
    counts = [int(n) for n in args.n.split(",")]
    clocks, modes = args.clock.split(","), args.mode.split(",")
    unknown = sorted(set(modes) - set(REPLIES))
    if unknown:
        parser.error(f"unknown mode(s) {', '.join(unknown)}: use {', '.join(REPLIES)}")
    if args.steps < 3:
        parser.error("--steps must be at least 3 (a first, a steady and a last step)")
    os.environ[KEY_ENV] = "sk-density-benchmark"  # the workers of the private Ray inherit it
    template = CacheTemplate.for_node(default_chromium(), EditorAssets().bundle_version)
    cache = "off" if template is None else f"{'present' if template.exists else 'none yet'} ({template.path})"
    rows: list[Row] = []
    with DelayedModel(args.delay) as model:
        for mode, clock, n in itertools.product(modes, clocks, counts):
            for run in range(args.repeat):
                started = time.perf_counter()
                rows.append(measure(n, clock, mode, run, args, model))
                print(
                    f"{mode} {clock} N={n} run {run + 1}: sweep took {time.perf_counter() - started:.0f} s",
                    file=sys.stderr,
                )
    print(f"{args.steps} steps per episode, model answering after {args.delay:g} s, {os.cpu_count()} core(s)")
    print(f"browser cache template at the first run's start: {cache}")
    print(HEADER)
    for row in rows:
        print(line(row))
        for problem in row.problems:
            print(f"  {row.mode} {row.clock} N={row.n}: {problem}")
    print("the model server's replies past their due time, p50/p95 (its own lag, in its own process):")
    for row in rows:
        print(f"  {row.mode} {row.clock} N={row.n}: {row.model_late[0] * 1000:.1f}/{row.model_late[1] * 1000:.1f} ms")
    print("where the cores went, per phase (CPU-ms per model call in brackets):")
    for row in rows:
        for phase in row.phases:
            print(f"  {row.mode} {row.clock} N={row.n} {phase.line()}")
    print("targets:")
    for verdict in targets(rows):
        print(f"  {verdict}")


if __name__ == "__main__":
    main()
