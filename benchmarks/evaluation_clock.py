"""Prints per-evaluation wall time under the virtual and the real clock, and the ratio, for a suite.

    .venv/bin/python benchmarks/evaluation_clock.py [--suite PATH] [--tasks a,b] [--profile native|upstream]

Every golden and initial project of the suite (ours by default) is evaluated once per clock, the
two clocks back to back for each project (alternating which goes first) so that machine load hits
both alike. Each evaluation gets a fresh editor and nothing else runs meanwhile: an editor starting
up beside a virtual-time evaluation takes CPU from it (an editor pool does exactly that).
Columns: verdict (passed/total or error kind) per clock, script-phase wall seconds per clock,
simulated seconds of the virtual run, the script-phase ratio real/virtual, and whole-evaluation
wall seconds (fresh editor, profile, project load, script).
A verdict that differs between the clocks is marked; the exit status is 1 if any does.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import statistics
import time
from pathlib import Path

from scratchworld_dist import load_suite
from workers import BrowserSession, EvalResult, EvaluationClock, EvaluationProfile, Evaluator

REPO = Path(__file__).resolve().parents[1]
CLOCKS: tuple[EvaluationClock, EvaluationClock] = ("virtual", "real")


def verdict(result: EvalResult) -> str:
    return result.error.kind if result.error else f"{result.passed}/{result.total}"


async def measure(suite_dir: Path, task_ids: list[str] | None, profile: EvaluationProfile | None) -> int:
    suite = load_suite(suite_dir)
    tasks = suite.select(ids=task_ids)
    print(f"suite {suite.name} ({suite.kind}), {len(tasks)} task(s); load average {os.getloadavg()[0]:.1f}")
    header = f"{'task':42} {'project':8} {'virtual':>8} {'real':>8} {'v script':>9} {'r script':>9} {'simul.':>7}"
    print(f"{header} {'ratio':>6} {'v total':>8} {'r total':>8}")
    totals: dict[EvaluationClock, dict[str, float]] = {c: {"script": 0.0, "total": 0.0} for c in CLOCKS}
    ratios: list[float] = []
    mismatches: list[str] = []
    started = time.perf_counter()
    async with BrowserSession() as session:
        evaluator = Evaluator(session)
        for task in tasks:
            projects = [("golden", task.golden_project), ("initial", task.initial_project)]
            for which, path in projects:
                if path is None:
                    continue
                data = path.read_bytes()
                order = CLOCKS if len(ratios) % 2 == 0 else CLOCKS[::-1]
                results = {
                    clock: await evaluator.evaluate(data, task.evaluation_spec(profile, clock)) for clock in order
                }
                virtual, real = results["virtual"], results["real"]
                for clock, result in results.items():
                    totals[clock]["script"] += result.timings.script_s or 0.0
                    totals[clock]["total"] += result.timings.total_s
                v_script, r_script = virtual.timings.script_s or 0.0, real.timings.script_s or 0.0
                ratio = r_script / v_script if v_script else float("nan")
                ratios.append(ratio)
                same = (virtual.success, virtual.passed, virtual.total) == (real.success, real.passed, real.total)
                if not same:
                    mismatches.append(f"{task.id} {which}")
                simulated = virtual.timings.script_clock_s or 0.0
                print(
                    f"{task.id[:42]:42} {which:8} {verdict(virtual):>8} {verdict(real):>8} {v_script:9.2f} "
                    f"{r_script:9.2f} {simulated:7.1f} {ratio:6.1f} {virtual.timings.total_s:8.2f} "
                    f"{real.timings.total_s:8.2f}{'' if same else '  <== verdicts differ'}",
                    flush=True,
                )
    v, r = totals["virtual"], totals["real"]
    print(f"\n{len(ratios)} evaluations per clock in {time.perf_counter() - started:.0f} s of benchmark wall time")
    for phase, label in (("script", "script phase:    "), ("total", "whole evaluation:")):
        print(f"{label} virtual {v[phase]:7.1f} s, real {r[phase]:7.1f} s, ratio {r[phase] / v[phase]:.1f}x")
    spread = f"min {min(ratios):.1f}, max {max(ratios):.1f}"
    print(f"per-evaluation script ratio: median {statistics.median(ratios):.1f}x ({spread})")
    print(
        f"verdicts differing between the clocks: {len(mismatches)}"
        + (f" ({', '.join(mismatches)})" if mismatches else "")
    )
    print(f"load average at the end: {os.getloadavg()[0]:.1f}")
    return 1 if mismatches else 0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--suite", type=Path, default=REPO / "tasks", help="suite folder (default: ours)")
    parser.add_argument("--tasks", help="comma-separated task ids (default: all)")
    parser.add_argument("--profile", choices=["native", "upstream"], help="evaluation profile (default: the suite's)")
    args = parser.parse_args()
    task_ids = [t.strip() for t in args.tasks.split(",") if t.strip()] if args.tasks else None
    raise SystemExit(asyncio.run(measure(args.suite, task_ids, args.profile)))


if __name__ == "__main__":
    main()
