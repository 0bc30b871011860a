"""Prints per-evaluation wall time under the virtual and the real clock, and the ratio, for a suite.

    .venv/bin/python benchmarks/evaluation_clock.py [--suite PATH] [--tasks a,b] [--profile native|upstream] [--fresh]

Every golden and initial project of the suite (ours by default) is evaluated once per clock, the
two clocks back to back for each project (alternating which goes first) so that machine load hits
both alike. Each clock has its own editor pool, as ``scratchworld validate`` uses it: an editor is
recycled and reused after each evaluation (``--fresh``: a fresh editor for every evaluation, no
pool). The first evaluation per clock includes the editor's start-up.
Columns: verdict (passed/total or error kind) per clock, whole-evaluation wall seconds per clock
(editor, profile, project load, script), the ratio real/virtual, script-phase wall seconds per
clock and the simulated seconds of the virtual run.
A verdict that differs between the clocks is marked; the exit status is 1 if any does.
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import os
import statistics
import time
from pathlib import Path

from scratchworld_dist import load_suite
from workers.contract import EvalResult, EvaluationClock, EvaluationProfile
from workers.editor import BrowserSession, EditorPool
from workers.evaluation import Evaluator

REPO = Path(__file__).resolve().parents[1]
CLOCKS: tuple[EvaluationClock, EvaluationClock] = ("virtual", "real")


def verdict(result: EvalResult) -> str:
    return result.error.kind if result.error else f"{result.passed}/{result.total}"


async def measure(suite_dir: Path, task_ids: list[str] | None, profile: EvaluationProfile | None, fresh: bool) -> int:
    suite = load_suite(suite_dir)
    tasks = suite.select(ids=task_ids)
    how = "a fresh editor per evaluation" if fresh else "editors recycled (one pool per clock)"
    print(f"suite {suite.name} ({suite.kind}), {len(tasks)} task(s), {how}; load average {os.getloadavg()[0]:.1f}")
    header = f"{'task':32} {'project':8} {'virtual':>8} {'real':>8} {'v total':>8} {'r total':>8} {'ratio':>6}"
    print(f"{header} {'v script':>9} {'r script':>9} {'simul.':>7}")
    totals: dict[EvaluationClock, dict[str, float]] = {c: {"script": 0.0, "total": 0.0} for c in CLOCKS}
    ratios: list[float] = []
    mismatches: list[str] = []
    started = time.perf_counter()
    async with BrowserSession() as session, contextlib.AsyncExitStack() as stack:
        pools = {
            clock: None if fresh else await stack.enter_async_context(EditorPool(session, spare=0)) for clock in CLOCKS
        }
        evaluators = {clock: Evaluator(session, pools[clock]) for clock in CLOCKS}
        for task in tasks:
            for which, path in (("golden", task.golden_project), ("initial", task.initial_project)):
                if path is None:
                    continue
                data = path.read_bytes()
                order = CLOCKS if len(ratios) % 2 == 0 else CLOCKS[::-1]
                results = {
                    clock: await evaluators[clock].evaluate(data, task.evaluation_spec(profile, clock))
                    for clock in order
                }
                virtual, real = results["virtual"], results["real"]
                for clock, result in results.items():
                    totals[clock]["script"] += result.timings.script_s or 0.0
                    totals[clock]["total"] += result.timings.total_s
                ratio = real.timings.total_s / virtual.timings.total_s
                ratios.append(ratio)
                same = (virtual.success, virtual.passed, virtual.total) == (real.success, real.passed, real.total)
                if not same:
                    mismatches.append(f"{task.id} {which}")
                print(
                    f"{task.id[:32]:32} {which:8} {verdict(virtual):>8} {verdict(real):>8} "
                    f"{virtual.timings.total_s:8.2f} {real.timings.total_s:8.2f} {ratio:6.1f} "
                    f"{virtual.timings.script_s or 0.0:9.2f} {real.timings.script_s or 0.0:9.2f} "
                    f"{virtual.timings.script_clock_s or 0.0:7.1f}{'' if same else '  <== verdicts differ'}",
                    flush=True,
                )
        for clock, pool in pools.items():
            if pool is not None:
                print(
                    f"{clock} pool: {pool.opened} editor(s) opened, {pool.reused} reuse(s), "
                    f"closed: {dict(pool.discarded)}"
                )
    v, r = totals["virtual"], totals["real"]
    print(f"\n{len(ratios)} evaluations per clock in {time.perf_counter() - started:.0f} s of benchmark wall time")
    for phase, label in (("total", "whole suite (evaluations):"), ("script", "script phase:             ")):
        print(f"{label} virtual {v[phase]:7.1f} s, real {r[phase]:7.1f} s, ratio {r[phase] / v[phase]:.1f}x")
    spread = f"min {min(ratios):.1f}, max {max(ratios):.1f}"
    print(f"per-evaluation ratio (whole evaluation): median {statistics.median(ratios):.1f}x ({spread})")
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
    parser.add_argument("--fresh", action="store_true", help="a fresh editor for every evaluation (no pool)")
    args = parser.parse_args()
    task_ids = [t.strip() for t in args.tasks.split(",") if t.strip()] if args.tasks else None
    raise SystemExit(asyncio.run(measure(args.suite, task_ids, args.profile, args.fresh)))


if __name__ == "__main__":
    main()
