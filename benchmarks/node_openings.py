"""Prints how long a node's browsers take to fill their editor pools, as a sweep's workers do before its first job.

    .venv/bin/python benchmarks/node_openings.py [--browsers 2] [--editors 16] [--runs 2]

Each run starts ``--browsers`` browsers at once (one per core, as a node runs its workers), each opening
``--editors`` editors into its pool one after another (``OPENS_AT_ONCE``), every one parked as it is ready:
the part of a sweep's start that ``density.py``'s ``start`` phase is mostly made of, without Ray, the model
server or the workers' imports around it. Printed per run: the wall time from the browsers' launch to the
last pool full, and the CPU seconds of this process and every one below it (browsers, their Playwright
drivers), per editor. The browsers start from the node's cache template, as a worker's do.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import time

from editor_openings import tree_cpu_s

from workers.actor._job_worker import OPENS_AT_ONCE
from workers.editor import BrowserConfig, BrowserSession, EditorPool


async def filled(editors: int) -> tuple[BrowserSession, EditorPool]:
    session = await BrowserSession(BrowserConfig(concurrent_opens=OPENS_AT_ONCE)).start()
    pool = EditorPool(session, spare=0)
    await pool.fill(editors)
    return session, pool


async def one_run(browsers: int, editors: int) -> tuple[float, float]:
    """Wall seconds and CPU seconds of ``browsers`` browsers filling ``editors`` each, at once."""
    cpu, started = tree_cpu_s(os.getpid()), time.monotonic()
    opened = await asyncio.gather(*(filled(editors) for _ in range(browsers)))
    wall, spent = time.monotonic() - started, tree_cpu_s(os.getpid()) - cpu
    for session, pool in opened:
        await pool.close()
        await session.close()
    return wall, spent


async def main(browsers: int, editors: int, runs: int) -> None:
    print(
        f"host: {os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.2f}; {browsers} browsers x {editors} editors"
    )
    for run in range(1, runs + 1):
        wall, spent = await one_run(browsers, editors)
        each = browsers * editors
        print(
            f"  run {run}: {wall:.1f} s, {spent:.0f} CPU-s ({spent / each:.2f} per editor, {wall / editors:.2f} s each)"
        )


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--browsers", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--editors", type=int, default=16)
    parser.add_argument("--runs", type=int, default=2)
    args = parser.parse_args()
    if args.browsers < 1 or args.editors < 1 or args.runs < 1:
        parser.error("--browsers, --editors and --runs must be at least 1")
    asyncio.run(main(args.browsers, args.editors, args.runs))
