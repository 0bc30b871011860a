"""Prints the size of each project's observable trace and what recording it costs, for a suite's projects.

    .venv/bin/python benchmarks/observable_trace.py [--suite PATH] [--tasks a,b] [--repeats 3] [--initials]

Every golden (``--initials``: and initial) project of the suite (ours by default) is evaluated
``--repeats`` times plainly and as many times with the trace recorded, alternating which goes first,
all in one recycled editor pool and under one ``Math.random`` seed, as the audit would run it.
Columns: verdict, trace frames recorded / VM steps run, trace JSON size, real ms the page spent
recording (snapshots, measured in the page: the trace's own cost), median wall seconds of the
script phase (the run in the page) and of the whole evaluation (with the trace's transfer and
validation) plainly and traced, and the difference of the medians. A verdict that differs with the
trace is marked; the exit status is 1 if any does.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import statistics
import sys
import time
from pathlib import Path

from scratchworld_dist import load_suite
from workers.contract import EvalResult, with_random_seed
from workers.editor import BrowserSession, EditorPool
from workers.evaluation import Evaluator, ObservableTrace

REPO = Path(__file__).resolve().parents[1]
SEED = 0


def verdict(result: EvalResult) -> str:
    return result.error.kind if result.error else f"{result.passed}/{result.total}"


async def measure(suite_dir: Path, task_ids: list[str] | None, repeats: int, initials: bool) -> int:
    suite = load_suite(suite_dir)
    tasks = suite.select(ids=task_ids)
    print(f"suite {suite.name}, {len(tasks)} task(s), {repeats} run(s) each way; load average {os.getloadavg()[0]:.1f}")
    print(
        f"{'task':28} {'project':8} {'verdict':>7} {'frames':>6} {'steps':>5} {'kB':>6} "
        f"{'rec ms':>6} {'script':>7} {'traced':>7} {'extra':>6} {'total':>7} {'traced':>7} {'extra':>6}"
    )
    mismatches: list[str] = []
    sizes: list[int] = []
    extra_script: list[float] = []
    extra_total: list[float] = []
    plain_script: list[float] = []
    recorded: list[float] = []
    started = time.perf_counter()
    async with BrowserSession() as session, EditorPool(session, spare=0) as pool:
        evaluator = Evaluator(session, pool)
        warm = tasks[0]
        await evaluator.evaluate(warm.initial_project.read_bytes(), warm.evaluation_spec())  # editor start-up
        for task in tasks:
            spec = task.evaluation_spec()
            projects = [("golden", task.golden_project)] + ([("initial", task.initial_project)] if initials else [])
            for which, path in projects:
                if path is None:
                    continue
                data = path.read_bytes()
                plain: list[EvalResult] = []
                traced: list[EvalResult] = []
                recording_s: list[float] = []
                trace: ObservableTrace | None = None
                for run in range(repeats):
                    for recording in (run % 2 == 0, run % 2 == 1):
                        if recording:
                            done = await evaluator.evaluate_traced(data, spec, random_seed=SEED)
                            traced.append(done.result)
                            recording_s.append(done.record_s or 0.0)
                            trace = done.trace
                        else:
                            plain.append(await evaluator.evaluate(data, with_random_seed(spec, SEED)))
                same = {verdict(r) for r in plain} == {verdict(r) for r in traced} and len(
                    {verdict(r) for r in plain}
                ) == 1
                if not same:
                    mismatches.append(f"{task.id} {which}")
                script = [statistics.median(r.timings.script_s or 0.0 for r in rs) for rs in (plain, traced)]
                total = [statistics.median(r.timings.total_s for r in rs) for rs in (plain, traced)]
                size = trace.chars if trace else 0
                sizes.append(size)
                recorded.append(statistics.median(recording_s))
                extra_script.append(script[1] - script[0])
                extra_total.append(total[1] - total[0])
                plain_script.append(script[0])
                print(
                    f"{task.id[:28]:28} {which:8} {verdict(plain[0]):>7} {len(trace.frames) if trace else 0:6} "
                    f"{trace.steps if trace else 0:5} {size / 1000:6.1f} {recorded[-1] * 1000:6.1f} "
                    f"{script[0]:7.2f} {script[1]:7.2f} {script[1] - script[0]:+6.2f} "
                    f"{total[0]:7.2f} {total[1]:7.2f} {total[1] - total[0]:+6.2f}"
                    f"{'' if same else '  <== verdicts differ'}",
                    flush=True,
                )
    print(
        f"trace size: median {statistics.median(sizes) / 1000:.1f} kB, max {max(sizes) / 1000:.1f} kB, "
        f"total {sum(sizes) / 1000:.1f} kB over {len(sizes)} project(s)"
    )
    print(
        f"recording in the page: median {statistics.median(recorded) * 1000:.1f} ms, "
        f"max {max(recorded) * 1000:.1f} ms per evaluation"
    )
    print(
        f"extra per evaluation (median of medians): script {statistics.median(extra_script) * 1000:+.0f} ms "
        f"({statistics.median(extra_script) / statistics.median(plain_script):+.0%} of the script phase), "
        f"whole evaluation {statistics.median(extra_total) * 1000:+.0f} ms; "
        f"{time.perf_counter() - started:.0f} s in all; load average {os.getloadavg()[0]:.1f}"
    )
    if mismatches:
        print(f"verdicts differ with the trace: {', '.join(mismatches)}")
    return 1 if mismatches else 0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--suite", type=Path, default=REPO / "tasks")
    parser.add_argument("--tasks", default=None, help="comma-separated task ids (default: all)")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--initials", action="store_true", help="also the initial projects")
    args = parser.parse_args()
    ids = args.tasks.split(",") if args.tasks else None
    sys.exit(asyncio.run(measure(args.suite, ids, max(1, args.repeats), args.initials)))


if __name__ == "__main__":
    main()
