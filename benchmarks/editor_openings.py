"""Prints the CPU-s each editor opening costs, first vs second vs third and later, per isolation setting.

    .venv/bin/python benchmarks/editor_openings.py [--openings 6] [--isolation origin,context] [--pages editor,bare]
        [--start fresh,template] [--palette held,drawn]

Each (isolation, page, start) gets a fresh browser, which opens ``--openings`` pages one after another,
each closed before the next opens, so no open VM inflates the figure. An opening's cost is the CPU
time of the whole Chromium tree (from /proc, via psutil: live processes plus the exited ones their
parents reaped) from the start of the opening to a ready page. With ``origin`` (one long-lived
context, an origin per editor) V8's code cache serves the bundle from the third opening on; with
``context`` (a fresh context per editor) every opening compiles it. ``--start``: ``fresh``, a browser
with an empty profile (no cache template); ``template``, a browser started from a cache template that
a first browser (not measured) left after opening two pages of each kind (``origin`` only: the other keeps
no cache on disk). ``--palette``: ``held``, editors opened as a pool opens them, the palette left undrawn
until a first project load; ``drawn``, as ``BrowserSession.open_editor`` opens them by default, the default
project's palette drawn before the editor counts as ready.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import statistics
import tempfile

import psutil

from workers.contract import EvaluationPage
from workers.editor import BrowserConfig, BrowserSession
from workers.editor._browser import EditorIsolation
from workers.editor._cache_template import TEMPLATE_ENV


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


async def openings(isolation: EditorIsolation, page: EvaluationPage, count: int, draw_palette: bool) -> list[float]:
    costs = []
    async with BrowserSession(BrowserConfig(editor_isolation=isolation)) as session:
        root = await session.browser_pid()
        for _ in range(count):
            before = tree_cpu_s(root)
            editor = await session.open_editor(page, draw_palette=draw_palette)
            costs.append(tree_cpu_s(root) - before)
            await editor.close()
    return costs


def summary(costs: list[float]) -> str:
    later = costs[2:]
    rest = f"3rd+ median {statistics.median(later):.2f} (min {min(later):.2f}, max {max(later):.2f})" if later else ""
    return f"1st {costs[0]:.2f}, 2nd {costs[1]:.2f}, {rest}  [{', '.join(f'{c:.2f}' for c in costs)}]"


async def leave_template(pages: list[EvaluationPage]) -> None:
    """A browser that opens two of each page and closes, leaving the cache template (not measured)."""
    async with BrowserSession(BrowserConfig(editor_isolation="origin")) as session:
        for page in dict.fromkeys(("editor", *pages)):  # two editors are what leaves a template
            for _ in range(2):
                await (await session.open_editor(page)).close()


async def main(
    count: int, isolations: list[EditorIsolation], pages: list[EvaluationPage], starts: list[str], palettes: list[str]
) -> None:
    print(f"host: {os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.2f}; CPU-s per opening:")
    with tempfile.TemporaryDirectory(prefix="editor-openings-") as templates:
        for start in starts:
            os.environ[TEMPLATE_ENV] = templates if start == "template" else "off"
            if start == "template":
                await leave_template(pages)
            for page in pages:
                for isolation in isolations:
                    if start == "template" and isolation != "origin":
                        continue
                    for palette in palettes if page == "editor" else ["-"]:
                        costs = await openings(isolation, page, count, palette != "held")
                        print(f"  {page:6s} {isolation:7s} {start:8s} {palette:5s} {summary(costs)}", flush=True)
    print(f"load average after: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--openings", type=int, default=6)
    parser.add_argument("--isolation", default="origin,context")
    parser.add_argument("--pages", default="editor,bare")
    parser.add_argument("--start", default="fresh,template")
    parser.add_argument("--palette", default="held,drawn")
    args = parser.parse_args()
    if args.openings < 3:
        parser.error("--openings must be at least 3 (first, second, third and later)")
    if not set(args.start.split(",")) <= {"fresh", "template"}:
        parser.error("--start takes fresh and/or template")
    if not set(args.palette.split(",")) <= {"held", "drawn"}:
        parser.error("--palette takes held and/or drawn")
    asyncio.run(
        main(
            args.openings,
            args.isolation.split(","),
            args.pages.split(","),
            args.start.split(","),
            args.palette.split(","),
        )  # type: ignore[arg-type]
    )
