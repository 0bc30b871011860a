"""Prints per-evaluation wall time under the virtual and the real clock, and the ratio, for a suite.

    .venv/bin/python benchmarks/evaluation_clock.py [--suite PATH] [--tasks a,b] [--task-list FILE]
        [--profile native|upstream] [--parallel N] [--fresh]

Every golden and initial project of the suite (ours by default) is evaluated once per clock, the
two clocks back to back for each project (alternating which goes first) so that machine load hits
both alike; ``--parallel`` projects at a time. Each clock has its own editor pool, as ``scratchworld
validate`` uses it: a page is recycled and reused after each evaluation (``--fresh``: a fresh page
for every evaluation, no pool). The first evaluation per clock includes the page's start-up.
Columns: verdict (passed/total or error kind) per clock, whole-evaluation wall seconds per clock
(page, profile, project load, script), the ratio real/virtual, script-phase wall seconds per
clock and the simulated seconds of the virtual run.
Verdicts are compared test by test. A test the suite's known stability names unstable (see
``scratchworld flakes --stability-out``) is compared apart: the clocks must agree on every other test.
The exit status is 1 if a verdict on a test not known to be unstable differs.
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
from scratchworld_dist.suites import Task, known_stability
from workers.contract import EvalResult, EvaluationClock, EvaluationProfile
from workers.editor import BrowserSession, EditorPool
from workers.evaluation import Evaluator

REPO = Path(__file__).resolve().parents[1]
CLOCKS: tuple[EvaluationClock, EvaluationClock] = ("virtual", "real")


def verdict(result: EvalResult) -> str:
    return result.error.kind if result.error else f"{result.passed}/{result.total}"


def tests_of(result: EvalResult) -> dict[str, str]:
    """Each test's verdict; a failed evaluation is one verdict of its own."""
    if result.error:
        return {"(evaluation)": result.error.kind}
    return {test.name: "pass" if test.passed else "fail" for test in result.tests}


def differing(virtual: EvalResult, real: EvalResult) -> set[str]:
    a, b = tests_of(virtual), tests_of(real)
    return {name for name in a.keys() | b.keys() if a.get(name) != b.get(name)}


async def measure(
    suite_dir: Path,
    task_ids: list[str] | None,
    task_list: str | None,
    profile: EvaluationProfile | None,
    parallel: int,
    fresh: bool,
) -> int:
    suite = load_suite(suite_dir, task_list=task_list)
    tasks = suite.select(ids=task_ids)
    known = known_stability(suite)
    how = "a fresh page per evaluation" if fresh else "pages recycled (one pool per clock)"
    print(
        f"suite {suite.name} ({suite.kind}), {len(tasks)} task(s), {how}, {parallel} project(s) at a time; "
        f"load average {os.getloadavg()[0]:.1f}"
    )
    covered = [task for task in tasks if known is not None and known.unstable_tests(task) is not None]
    print(f"known test stability covers {len(covered)} of {len(tasks)} task(s)")
    header = f"{'task':32} {'project':8} {'virtual':>8} {'real':>8} {'v total':>8} {'r total':>8} {'ratio':>6}"
    print(f"{header} {'v script':>9} {'r script':>9} {'simul.':>7}")
    totals: dict[EvaluationClock, dict[str, float]] = {c: {"script": 0.0, "total": 0.0} for c in CLOCKS}
    ratios: list[float] = []
    tests_compared = {"stable": 0, "unstable": 0, "unchecked": 0}
    mismatches: dict[str, list[str]] = {"stable": [], "unstable": [], "unchecked": []}
    slots = asyncio.Semaphore(parallel)
    started = time.perf_counter()
    async with BrowserSession() as session, contextlib.AsyncExitStack() as stack:
        pools = {
            clock: None if fresh else await stack.enter_async_context(EditorPool(session, spare=0)) for clock in CLOCKS
        }
        evaluators = {clock: Evaluator(session, pools[clock]) for clock in CLOCKS}

        async def one(task: Task, which: str, data: bytes, index: int) -> None:
            order = CLOCKS if index % 2 == 0 else CLOCKS[::-1]
            async with slots:
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
            unstable = known.unstable_tests(task) if known is not None else None

            def kind_of(name: str) -> str:
                return "unchecked" if unstable is None else "unstable" if name in unstable else "stable"

            for name in tests_of(virtual).keys() | tests_of(real).keys():
                tests_compared[kind_of(name)] += 1
            notes = []
            for name in sorted(differing(virtual, real)):
                kind = kind_of(name)
                mismatches[kind].append(f"{task.id} {which} {name!r}")
                notes.append(f"{name!r} ({kind})")
            print(
                f"{task.id[:32]:32} {which:8} {verdict(virtual):>8} {verdict(real):>8} "
                f"{virtual.timings.total_s:8.2f} {real.timings.total_s:8.2f} {ratio:6.1f} "
                f"{virtual.timings.script_s or 0.0:9.2f} {real.timings.script_s or 0.0:9.2f} "
                f"{virtual.timings.script_clock_s or 0.0:7.1f}"
                + (f"  <== differs: {', '.join(notes)}" if notes else ""),
                flush=True,
            )

        projects = [
            (task, which, path.read_bytes())
            for task in tasks
            for which, path in (("golden", task.golden_project), ("initial", task.initial_project))
            if path is not None
        ]
        async with asyncio.TaskGroup() as group:
            for index, (task, which, data) in enumerate(projects):
                group.create_task(one(task, which, data, index))
        for clock, pool in pools.items():
            if pool is not None:
                print(
                    f"{clock} pool: {pool.opened} page(s) opened, {pool.reused} reuse(s), "
                    f"closed: {dict(pool.discarded)}"
                )
    v, r = totals["virtual"], totals["real"]
    print(f"\n{len(ratios)} evaluations per clock in {time.perf_counter() - started:.0f} s of benchmark wall time")
    for phase, label in (("total", "whole suite (evaluations):"), ("script", "script phase:             ")):
        print(f"{label} virtual {v[phase]:7.1f} s, real {r[phase]:7.1f} s, ratio {r[phase] / v[phase]:.1f}x")
    spread = f"min {min(ratios):.1f}, max {max(ratios):.1f}"
    print(f"per-evaluation ratio (whole evaluation): median {statistics.median(ratios):.1f}x ({spread})")
    for kind in ("stable", "unstable", "unchecked"):
        found = mismatches[kind]
        print(
            f"test verdicts differing between the clocks, {kind} tests: {len(found)} of {tests_compared[kind]}"
            + (f" ({'; '.join(found)})" if found else "")
        )
    print(f"load average at the end: {os.getloadavg()[0]:.1f}")
    return 1 if mismatches["stable"] or mismatches["unchecked"] else 0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--suite", type=Path, default=REPO / "tasks", help="suite folder (default: ours)")
    parser.add_argument("--tasks", help="comma-separated task ids (default: all)")
    parser.add_argument("--task-list", help="an upstream clone's task list (a file, or a name under tasks/)")
    parser.add_argument("--profile", choices=["native", "upstream"], help="evaluation profile (default: the suite's)")
    parser.add_argument("--parallel", type=int, default=1, help="projects evaluated at a time (default 1)")
    parser.add_argument("--fresh", action="store_true", help="a fresh page for every evaluation (no pool)")
    args = parser.parse_args()
    if args.parallel < 1:
        parser.error("--parallel must be at least 1")
    task_ids = [t.strip() for t in args.tasks.split(",") if t.strip()] if args.tasks else None
    raise SystemExit(
        asyncio.run(measure(args.suite, task_ids, args.task_list, args.profile, args.parallel, args.fresh))
    )


if __name__ == "__main__":
    main()
