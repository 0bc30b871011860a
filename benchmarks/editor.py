"""Prints the editor's costs: ready time, project load time, evaluation wall time per task, memory.

    .venv/bin/python benchmarks/editor.py [--repeats 5] [--editors 4] [--skip-validate]

Figures are wall-clock on whatever machine runs this (note its load); memory is the PSS of the
Chromium process tree (RSS double-counts pages shared between Chromium processes).
It also measures the serving alternative we did not choose (Playwright routing every request
from disk instead of a loopback static server), to keep that decision measured.
"""

from __future__ import annotations

import argparse
import asyncio
import mimetypes
import os
import statistics
import time
from pathlib import Path

from playwright.async_api import Route

from scratchworld_dist import load_suite, validate_tasks
from workers.editor import BrowserSession, Editor, EditorAssets

REPO = Path(__file__).resolve().parents[1]
UPSTREAM_PONG = REPO.parent / "shared" / "scratchworld-upstream" / "scratch-gui" / "static" / "pong_starter_golden.sb3"


def describe(values: list[float]) -> str:
    return f"median {statistics.median(values):.2f} s (min {min(values):.2f}, max {max(values):.2f}, n={len(values)})"


def descendants(pid: int) -> list[int]:
    children: dict[int, list[int]] = {}
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                parent = int((entry / "stat").read_text().rsplit(")", 1)[1].split()[1])
            except (OSError, IndexError, ValueError):
                continue
            children.setdefault(parent, []).append(int(entry.name))
    found, stack = [], [pid]
    while stack:
        for child in children.get(stack.pop(), []):
            found.append(child)
            stack.append(child)
    return found


def chromium_pss_mb() -> float:
    """PSS of every Chromium process started by this Python process."""
    total_kb = 0
    for pid in descendants(os.getpid()):
        try:
            if "chrom" not in Path(f"/proc/{pid}/comm").read_text():
                continue
            for line in Path(f"/proc/{pid}/smaps_rollup").read_text().splitlines():
                if line.startswith("Pss:"):
                    total_kb += int(line.split()[1])
        except OSError:
            continue
    return total_kb / 1024


async def ready_times(session: BrowserSession, repeats: int) -> list[float]:
    times = []
    for _ in range(repeats):
        async with session.editor() as editor:
            assert editor.ready_s is not None
            times.append(editor.ready_s)
    return times


async def routed_ready_times(session: BrowserSession, repeats: int) -> list[float]:
    """Ready time when Playwright fulfils every request from disk (the alternative to a server)."""
    assets = EditorAssets()

    async def fulfil(route: Route) -> None:
        path = assets.resolve(route.request.url.split("://", 1)[1].split("/", 1)[1])
        if path is None:
            await route.fulfill(status=404)
        else:
            await route.fulfill(
                path=path, content_type=mimetypes.guess_type(path.name)[0] or "application/octet-stream"
            )

    times = []
    for _ in range(repeats):
        context = await session.new_context()
        await context.route("http://editor.invalid/**", fulfil)
        editor = Editor(context, await context.new_page())
        started = time.perf_counter()
        await editor.open("http://editor.invalid/index.html", 60)
        times.append(time.perf_counter() - started)
        await editor.close()
    return times


async def load_times(session: BrowserSession, projects: list[Path]) -> list[tuple[str, int, float]]:
    rows = []
    async with session.editor() as editor:
        for path in projects:
            data = path.read_bytes()
            started = time.perf_counter()
            await editor.load_project(data)
            rows.append((path.parent.name + "/" + path.name, len(data), time.perf_counter() - started))
    return rows


async def memory(session: BrowserSession, editors: int, project: bytes) -> list[tuple[int, float]]:
    rows = [(0, chromium_pss_mb())]
    opened: list[Editor] = []
    try:
        for count in range(1, editors + 1):
            editor = await session.open_editor()
            await editor.load_project(project)
            opened.append(editor)
            rows.append((count, chromium_pss_mb()))
    finally:
        for editor in opened:
            await editor.close()
    return rows


async def main(repeats: int, editors: int, skip_validate: bool) -> None:
    print(f"host: {os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.2f}")
    started = time.perf_counter()
    async with BrowserSession() as session:
        print(f"browser launch + editor server: {time.perf_counter() - started:.2f} s")
        print(f"editor ready (fresh context, loopback server): {describe(await ready_times(session, repeats))}")
        print(f"editor ready (Playwright routing instead):     {describe(await routed_ready_times(session, repeats))}")

        projects = sorted((REPO / "tasks").glob("*/*/golden.sb3"))
        if UPSTREAM_PONG.is_file():
            projects.append(UPSTREAM_PONG)
        print("project load (bytes -> VM, through the bridge):")
        for name, size, seconds in await load_times(session, projects):
            print(f"  {name:55s} {size / 1024:7.1f} KB  {seconds:.3f} s")

        largest = max(projects, key=lambda p: p.stat().st_size).read_bytes()
        print("memory (PSS of the Chromium tree, each editor with a project loaded):")
        previous = None
        for count, pss in await memory(session, editors, largest):
            extra = f"  (+{pss - previous:.0f} MB)" if previous is not None else ""
            print(f"  {count} editor(s): {pss:7.0f} MB{extra}")
            previous = pss

    if not skip_validate:
        suite = load_suite(REPO / "tasks")
        print(f"evaluation wall time per task (fresh editor -> verdict, 1 editor at a time, {suite.name}):")
        rows = await validate_tasks(list(suite.tasks), parallel=1)
        for row in rows:
            golden = f"{row.golden.wall_s:6.1f} s" if row.golden else "   -  "
            print(f"  {row.category:8s} {row.task_id:32s} golden {golden}  initial {row.initial.wall_s:6.1f} s")
        walls = [c.wall_s for r in rows for c in (r.golden, r.initial) if c is not None]
        print(f"  total {sum(walls):.0f} s over {len(walls)} evaluations, {describe(walls)}")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--editors", type=int, default=4)
    parser.add_argument("--skip-validate", action="store_true")
    args = parser.parse_args()
    asyncio.run(main(args.repeats, args.editors, args.skip_validate))
