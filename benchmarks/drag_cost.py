"""Prints what a primitive drag costs, whole and in parts: wall time and the CPU of each kind of process.

    .venv/bin/python benchmarks/drag_cost.py [--project PATH.sb3] [--drags 12] [--rounds 2]

One editor on an episode's virtual clock (``Pace``, as a primitive episode has it) drags a palette block into
the code area ``--drags`` times per row: the drag as episodes make it (``Gestures`` with the clock's advances
between its moves, its moves past Chromium's drag decision sent to the page directly, and the block links read
before and after), the same without the link reads, the same with every move through Playwright's drag
interception (``workers/primitive/_pressed_moves.py``), the moves alone (no clock: Playwright's interpolated
moves), and the parts alone (15 clock advances, two link reads, an action's lead and settle). CPU is per
drag, from the CPU seconds of this process ("driver": Python) and of every process below it, by kind
(``_process_sampler``: Chromium's by ``--type``, Playwright's driver), read before and after each row.
"""

from __future__ import annotations

import argparse
import asyncio
import time
from collections.abc import Awaitable, Callable
from pathlib import Path

from _process_sampler import Sampler

from workers.contract import EpisodeClock
from workers.editor import BrowserSession
from workers.kinds.tasks._pace import Pace
from workers.primitive import Gestures

REPO = Path(__file__).resolve().parents[1]
DEFAULT_PROJECT = REPO / "tasks" / "extend" / "quiz_score" / "initial.sb3"
DRAG = {"start_x": 60, "start_y": 250, "end_x": 500, "end_y": 300}
"""From the palette's column to the code area: a block is dragged out and dropped on each drag."""
MOVES = 15
"""A drag's moves at its default half second (``DragArgs.duration``: 30 a second)."""


async def measure(
    sampler: Sampler, work: Callable[[], Awaitable[object]], count: int
) -> tuple[float, dict[str, float]]:
    """Wall ms per call of ``work``, and CPU ms per call by kind (``sampler`` read before and after, not threaded)."""
    before, started = sampler.sample(), time.perf_counter()
    for _ in range(count):
        await work()
    wall_ms = (time.perf_counter() - started) / count * 1000
    after = sampler.sample()
    return wall_ms, {kind: (after.by_kind[kind] - before.by_kind[kind]) / count * 1000 for kind in after.by_kind}


async def main(project: bytes, drags: int, rounds: int) -> None:
    async with BrowserSession() as session, session.editor() as editor:
        await editor.load_project(project)
        await editor.set_stage_size("small")
        pace = Pace(editor, EpisodeClock(mode="virtual"))
        await pace.start()

        def links() -> Awaitable[object]:
            return editor.call("primitiveLinks")

        def dragging() -> Awaitable[object]:
            return editor.call("primitiveDragging")

        as_episodes = Gestures(editor.page, pace.pass_time, links=links, dragging=dragging)
        without_links = Gestures(editor.page, pace.pass_time, dragging=dragging)
        intercepted = Gestures(editor.page, pace.pass_time)
        moves_alone = Gestures(editor.page, None)

        async def advances() -> None:
            for _ in range(MOVES):
                await pace.pass_time(500 / MOVES)

        async def two_link_reads() -> None:
            await links()
            await links()

        async def lead_and_settle() -> None:
            await pace.before_action()
            await pace.after_action()

        rows: dict[str, Callable[[], Awaitable[object]]] = {
            "drag as episodes make it": lambda: as_episodes.execute("drag_and_drop", DRAG),
            "drag without link reads": lambda: without_links.execute("drag_and_drop", DRAG),
            "every move intercepted": lambda: intercepted.execute("drag_and_drop", DRAG),
            "moves alone (no clock)": lambda: moves_alone.execute("drag_and_drop", DRAG),
            f"{MOVES} clock advances": advances,
            "2 link reads": two_link_reads,
            "an action's lead and settle": lead_and_settle,
        }
        sampler = Sampler()
        sampler.sample()  # from here on, each kind's CPU counts from this reading
        for round_index in range(rounds):
            print(f"round {round_index + 1} ({drags} per row; ms per call):")
            for name, work in rows.items():
                wall_ms, cpu = await measure(sampler, work, drags)
                by_cost = sorted(cpu.items(), key=lambda kind_ms: -kind_ms[1])
                parts = "  ".join(f"{kind} {ms:.0f}" for kind, ms in by_cost if ms >= 1)
                print(f"  {name:28s} wall {wall_ms:5.0f}  CPU {sum(cpu.values()):5.0f}:  {parts}")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--project", type=Path, default=DEFAULT_PROJECT)
    parser.add_argument("--drags", type=int, default=12)
    parser.add_argument("--rounds", type=int, default=2)
    args = parser.parse_args()
    asyncio.run(main(args.project.read_bytes(), args.drags, args.rounds))
