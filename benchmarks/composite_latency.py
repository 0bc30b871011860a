"""Prints composite-mode latency: p50/p95 per action kind and per observation, on a real project.

    .venv/bin/python benchmarks/composite_latency.py [--project maze_starter.sb3] [--sprite Ball] [--rounds 30]

Round trip is what an agent pays (Python -> page -> Python through the bridge); in-page is the
action's own time inside the page. The default project is the upstream Maze starter when the
upstream data is present, else our bouncing-ball task.
"""

from __future__ import annotations

import argparse
import asyncio
import statistics
import time
from collections import defaultdict
from pathlib import Path

from pydantic import JsonValue

from workers import composite
from workers.editor import BrowserSession, Editor

REPO = Path(__file__).resolve().parents[1]
MAZE = REPO.parent / "shared" / "scratchworld-upstream" / "scratch-gui" / "static" / "maze_starter.sb3"
FALLBACK = REPO / "tasks" / "debug" / "bouncing_ball_stuck" / "initial.sb3"


def percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, round(q * (len(ordered) - 1)))]


async def timed(
    editor: Editor, api: str, args: dict[str, JsonValue], laps: dict[str, list[tuple[float, float]]]
) -> dict:
    started = time.perf_counter()
    envelope = await composite.execute(editor, api, args)
    laps[api].append(((time.perf_counter() - started) * 1000, envelope.duration_ms))
    if not envelope.success:
        raise RuntimeError(f"{api} {args}: {envelope.error}")
    return envelope.data  # type: ignore[return-value]


async def one_round(editor: Editor, laps: dict[str, list[tuple[float, float]]]) -> None:
    """A realistic edit cycle that leaves the project as it found it."""
    started = time.perf_counter()
    observation = await composite.observe(editor)
    laps["observe"].append(((time.perf_counter() - started) * 1000, 0.0))
    count = observation.block_count
    hat = (await timed(editor, "add_block", {"blockType": "event_whenflagclicked"}, laps))["index"]
    move = (await timed(editor, "add_block", {"blockType": "motion_movesteps"}, laps))["index"]
    await timed(
        editor,
        "connect_blocks",
        {"sourceBlockIndex": move, "targetBlockIndex": hat, "placement": {"kind": "stack_after"}},
        laps,
    )
    await timed(editor, "set_block_field", {"blockIndex": count + 2, "fieldName": "STEPS", "value": 7}, laps)
    add = (await timed(editor, "add_block", {"blockType": "operator_add"}, laps))["index"]
    await timed(
        editor,
        "connect_blocks",
        {
            "sourceBlockIndex": add,
            "targetBlockIndex": count + 2,
            "placement": {"kind": "value_into", "inputName": "STEPS"},
        },
        laps,
    )
    await timed(editor, "detach_blocks", {"blockIndex": count + 2}, laps)
    await timed(editor, "delete_block", {"blockIndex": count + 1}, laps)
    await timed(editor, "delete_block", {"blockIndex": count + 1}, laps)


async def main(project: Path, sb3: bytes, sprite: str | None, rounds: int) -> None:
    laps: dict[str, list[tuple[float, float]]] = defaultdict(list)
    async with BrowserSession() as session, session.editor() as editor:
        await editor.load_project(sb3)
        targets = (await composite.observe(editor)).targets
        name = sprite or next(t.name for t in targets if not t.is_stage)
        await composite.execute(editor, "select_sprite", {"name": name})
        before = (await composite.observe(editor)).text
        await one_round(editor, defaultdict(list))  # warm-up: caches, JIT
        for _ in range(rounds):
            await one_round(editor, laps)
        assert (await composite.observe(editor)).text == before, "a round must leave the project unchanged"
    print(f"{project.name}, sprite {name}, {rounds} rounds (times in ms: round trip p50/p95, in-page p50)")
    for kind, values in sorted(laps.items()):
        trips, inside = [v[0] for v in values], [v[1] for v in values]
        print(
            f"  {kind:16s} n={len(values):4d}  p50 {statistics.median(trips):6.2f}  p95 {percentile(trips, 0.95):6.2f}"
            f"  in-page p50 {statistics.median(inside):6.2f}"
        )
    actions = [v[0] for kind, values in laps.items() if kind != "observe" for v in values]
    p50, p95 = statistics.median(actions), percentile(actions, 0.95)
    print(f"  {'all actions':16s} n={len(actions):4d}  p50 {p50:6.2f}  p95 {p95:6.2f}")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--project", type=Path, default=MAZE if MAZE.is_file() else FALLBACK)
    parser.add_argument("--sprite", help="sprite to edit (default: the first sprite)")
    parser.add_argument("--rounds", type=int, default=30)
    args = parser.parse_args()
    asyncio.run(main(args.project, args.project.read_bytes(), args.sprite, args.rounds))
