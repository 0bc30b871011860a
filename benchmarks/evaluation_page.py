"""Prints what an evaluation costs on the bare evaluation page and on the editor page, and whether they agree.

    .venv/bin/python benchmarks/evaluation_page.py [--suite PATH] [--task-list FILE] [--clock virtual|real]
        [--openings N]

For each page kind (``bare``, then ``editor``):
- ready: median seconds from navigation to a ready page over ``--openings`` fresh pages, and the CPU
  seconds each opening cost (browser processes and this one);
- PSS: proportional set size per page, from four pages open at once, over a browser with none;
- evaluations: every golden and initial of the suite, one page at a time, pages recycled as
  ``scratchworld validate`` does; the median project load, and **evaluations per core-second**: the
  evaluations over the CPU seconds they cost (browser processes and this one, pool start included).
Verdicts (passed/total and each test's outcome) are compared between the two pages; the exit status
is 1 if any differs.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import statistics
import time
from pathlib import Path

import psutil

from scratchworld_dist import load_suite
from scratchworld_dist.suites import Task
from workers.contract import EvalResult, EvaluationClock, EvaluationPage
from workers.editor import BrowserSession, EditorPool
from workers.evaluation import Evaluator
from workers.node import browser_usage

REPO = Path(__file__).resolve().parents[1]
PAGES: tuple[EvaluationPage, EvaluationPage] = ("bare", "editor")
PSS_PAGES = 4


def cpu_s() -> float:
    """CPU seconds so far of this process and its browsers."""
    own = psutil.Process().cpu_times()
    return own.user + own.system + browser_usage().cpu_s


def verdict(result: EvalResult) -> tuple[object, ...]:
    if result.error:
        return (result.error.kind,)
    return (result.passed, result.total, tuple((test.name, test.passed) for test in result.tests))


async def openings(session: BrowserSession, page: EvaluationPage, count: int) -> tuple[float, float]:
    """Median ready seconds and median CPU seconds per opening of a fresh page."""
    ready, cpu = [], []
    for _ in range(count):
        before = cpu_s()
        editor = await session.open_editor(page)
        cpu.append(cpu_s() - before)
        ready.append(editor.ready_s or 0.0)
        await editor.close()
    return statistics.median(ready), statistics.median(cpu)


async def pss_per_page(session: BrowserSession, page: EvaluationPage) -> float:
    baseline = browser_usage().pss_bytes
    editors = [await session.open_editor(page) for _ in range(PSS_PAGES)]
    try:
        return (browser_usage().pss_bytes - baseline) / PSS_PAGES
    finally:
        for editor in editors:
            await editor.close()


async def evaluations(
    session: BrowserSession, tasks: list[Task], page: EvaluationPage, clock: EvaluationClock | None
) -> tuple[dict[tuple[str, str], tuple[object, ...]], float, float, float]:
    """Verdicts per (task, project), evaluations per core-second, median project load and wall seconds."""
    jobs = [
        (task, which, path.read_bytes(), task.evaluation_spec(clock=clock, page=page))
        for task in tasks
        for which, path in (("golden", task.golden_project), ("initial", task.initial_project))
        if path is not None
    ]
    verdicts: dict[tuple[str, str], tuple[object, ...]] = {}
    loads: list[float] = []
    started, before = time.perf_counter(), cpu_s()
    async with EditorPool(session, spare=0) as pool:
        evaluator = Evaluator(session, pool)
        for task, which, project, spec in jobs:
            result = await evaluator.evaluate(project, spec)
            verdicts[(task.id, which)] = verdict(result)
            if result.timings.project_load_s is not None:
                loads.append(result.timings.project_load_s)
    spent = cpu_s() - before
    return verdicts, len(jobs) / spent, statistics.median(loads) if loads else 0.0, time.perf_counter() - started


async def measure(suite_dir: Path, task_list: str | None, clock: EvaluationClock | None, count: int) -> int:
    suite = load_suite(suite_dir, task_list=task_list)
    tasks = suite.select()
    print(
        f"suite {suite.name} ({suite.kind}), {len(tasks)} task(s), clock {clock or 'the suite default'}; "
        f"{os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.1f}"
    )
    print(
        f"{'page':7} {'ready s':>8} {'CPU s/open':>10} {'PSS MB':>7} {'evals':>6} {'evals/core-s':>12} "
        f"{'load s':>7} {'wall s':>7}"
    )
    results: dict[EvaluationPage, dict[tuple[str, str], tuple[object, ...]]] = {}
    rates: dict[EvaluationPage, float] = {}
    async with BrowserSession() as session:
        for page in PAGES:
            ready, open_cpu = await openings(session, page, count)
            pss = await pss_per_page(session, page)
            results[page], rates[page], load, wall = await evaluations(session, tasks, page, clock)
            print(
                f"{page:7} {ready:8.2f} {open_cpu:10.2f} {pss / 2**20:7.0f} {len(results[page]):6d} "
                f"{rates[page]:12.3f} {load:7.3f} {wall:7.1f}",
                flush=True,
            )
    differing = sorted(key for key in results["bare"] if results["bare"][key] != results["editor"].get(key))
    print(f"evaluations per core-second, bare over editor: {rates['bare'] / rates['editor']:.2f}x")
    print(f"verdicts identical on both pages: {len(results['bare']) - len(differing)} of {len(results['bare'])}")
    for task_id, which in differing:
        print(
            f"  DIFFERS {task_id} {which}: bare {results['bare'][(task_id, which)]} "
            f"editor {results['editor'].get((task_id, which))}"
        )
    return 1 if differing else 0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--suite", type=Path, default=REPO / "tasks")
    parser.add_argument("--task-list", help="A task list file (needed for an upstream clone with held-out scripts).")
    parser.add_argument("--clock", choices=["virtual", "real"], help="Evaluation clock (default: the suite's).")
    parser.add_argument("--openings", type=int, default=5, help="Fresh pages opened per kind for the ready time.")
    args = parser.parse_args()
    raise SystemExit(asyncio.run(measure(args.suite, args.task_list, args.clock, args.openings)))


if __name__ == "__main__":
    main()
