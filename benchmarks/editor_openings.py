"""Prints the CPU-s each editor opening costs, first vs second vs third and later, per isolation setting.

    .venv/bin/python benchmarks/editor_openings.py [--openings 6] [--isolation origin,context] [--pages editor,bare]

Each (isolation, page) pair gets a fresh browser, which opens ``--openings`` pages one after another,
each closed before the next opens, so no open VM inflates the figure. An opening's cost is the CPU
time of the whole Chromium tree (from /proc, via psutil: live processes plus the exited ones their
parents reaped) from the start of the opening to a ready page. With ``origin`` (one long-lived
context, an origin per editor) V8's code cache serves the bundle from the third opening on; with
``context`` (a fresh context per editor) every opening compiles it.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import statistics

import psutil

from workers.contract import EvaluationPage
from workers.editor import BrowserConfig, BrowserSession
from workers.editor._browser import EditorIsolation


def tree_cpu_s(root_pid: int) -> float:
    """User + system CPU of ``root_pid`` and everything under it, reaped children included."""
    total = 0.0
    try:
        processes = [psutil.Process(root_pid), *psutil.Process(root_pid).children(recursive=True)]
    except psutil.Error:
        return total
    for process in processes:
        try:
            times = process.cpu_times()
        except psutil.Error:
            continue
        total += times.user + times.system + times.children_user + times.children_system
    return total


async def openings(isolation: EditorIsolation, page: EvaluationPage, count: int) -> list[float]:
    costs = []
    async with BrowserSession(BrowserConfig(editor_isolation=isolation)) as session:
        root = await session.browser_pid()
        for _ in range(count):
            before = tree_cpu_s(root)
            editor = await session.open_editor(page)
            costs.append(tree_cpu_s(root) - before)
            await editor.close()
    return costs


def summary(costs: list[float]) -> str:
    later = costs[2:]
    rest = f"3rd+ median {statistics.median(later):.2f} (min {min(later):.2f}, max {max(later):.2f})" if later else ""
    return f"1st {costs[0]:.2f}, 2nd {costs[1]:.2f}, {rest}  [{', '.join(f'{c:.2f}' for c in costs)}]"


async def main(count: int, isolations: list[EditorIsolation], pages: list[EvaluationPage]) -> None:
    print(f"host: {os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.2f}; CPU-s per opening:")
    for page in pages:
        for isolation in isolations:
            print(f"  {page:6s} {isolation:7s} {summary(await openings(isolation, page, count))}", flush=True)
    print(f"load average after: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--openings", type=int, default=6)
    parser.add_argument("--isolation", default="origin,context")
    parser.add_argument("--pages", default="editor,bare")
    args = parser.parse_args()
    if args.openings < 3:
        parser.error("--openings must be at least 3 (first, second, third and later)")
    asyncio.run(main(args.openings, args.isolation.split(","), args.pages.split(",")))  # type: ignore[arg-type]
