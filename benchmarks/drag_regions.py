"""Exact drag regions against real drags: computation time per task, agreement, and upstream's cross-check.

For each task of each suite (default: our generated ``drag-tasks/`` and, when present, the upstream
clone at ``../shared/scratchworld-upstream``) the regions are computed in a real editor, then
checked by real drags, each in the task's freshly set-up view:

- end region: ``--boundary`` pixels just inside its edge and as many just outside, plus ``--interior``
  random pixels inside and as many outside (within 60 px of it), dragged from the fixed start;
- start region: ``--boundary`` pixels just inside and outside, each pressed and dragged by the offset
  that takes the fixed start to the end region's deepest pixel (a grab there connects).

``--boundary all`` drags from every boundary pixel of both regions (inside and out); with
``--per-kind`` (one task of each connection kind and source) it checks whole boundaries of a sample.

A sample agrees when the drag connects exactly when the region says it should. Upstream's own
``feasible_start_points`` and ``feasible_points`` (5 px grids in its editor) are compared with our
regions as they are, and at the integer offset (within 6 px) that best aligns the two layouts.

    .venv/bin/python benchmarks/drag_regions.py [SUITE ...] [--tasks N | --per-kind | --ids A,B]
        [--boundary K|all] [--interior M]
"""

from __future__ import annotations

import argparse
import asyncio
import random
import statistics
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from scratchworld_dist.kinds.drag.items import DragTask, load_drag_suite  # noqa: E402
from workers.contract import DragRegions, Point, Region  # noqa: E402
from workers.editor import BrowserConfig, BrowserSession, Editor, EditorPool  # noqa: E402
from workers.kinds.drag import DragPayload  # noqa: E402
from workers.kinds.drag import _page as page  # noqa: E402

UPSTREAM = REPO.parent / "shared" / "scratchworld-upstream"
NEAR = 60
OFFSETS = range(-6, 7)


@dataclass
class TaskFigures:
    task_id: str
    regions_s: float
    samples: int = 0
    agreed: int = 0
    disagreements: list[str] = field(default_factory=list)
    by_kind: dict[str, list[int]] = field(default_factory=dict)
    """``[agreed, samples]`` per kind of sample: end or start region, a point inside or outside it."""
    upstream: CrossCheck | None = None


def exterior(region: Region, rng: random.Random, count: int) -> list[Point]:
    inside = set(region.points())
    xs = [x for _, x0, x1 in region.rows for x in (x0, x1)]
    ys = [y for y, _, _ in region.rows]
    found: list[Point] = []
    for _ in range(count * 50):
        if len(found) == count:
            break
        p = (rng.randint(min(xs) - NEAR, max(xs) + NEAR), rng.randint(min(ys) - NEAR, max(ys) + NEAR))
        if p not in inside and 0 <= p[0] < 1280 and 0 <= p[1] < 720:
            found.append(p)
    return found


def share(points: tuple[Point, ...], region: Region, dx: int, dy: int) -> float:
    return sum(region.contains(x + dx, y + dy) for x, y in points) / len(points) if points else float("nan")


@dataclass
class CrossCheck:
    """One upstream task's own feasible points against our regions."""

    starts: float
    """Share of upstream's feasible starts inside our start region."""

    starts_aligned: float
    offset: tuple[int, int]
    """The shift (within 6 px) that puts most of upstream's starts in ours, and the share it puts there."""

    ends: float
    """Share of upstream's feasible ends, moved with the press to our fixed start, inside our end region
    (the move makes any layout offset cancel: an end is where the block goes relative to its grip)."""

    ends_found: float | None
    """Share of our end region's pixels on upstream's end grid that upstream lists (None: no grid)."""

    end_miss_px: list[float]
    """Distances to our end region of upstream's ends outside it."""


def cross_check(task: DragTask, regions: DragRegions) -> CrossCheck | None:
    up = task.upstream
    if up is None or not up.feasible_start_points or not up.feasible_points:
        return None
    # Upstream's ends are for a press at its drag_start_point: move them with the press to our fixed start.
    move = (regions.fixed_start[0] - up.drag_start_point[0], regions.fixed_start[1] - up.drag_start_point[1])
    ends = tuple((x + move[0], y + move[1]) for x, y in up.feasible_points)
    best = max(
        ((dx, dy) for dx in OFFSETS for dy in OFFSETS), key=lambda o: share(up.feasible_start_points, regions.start, *o)
    )
    found = None
    step = up.end_grid_step
    if step:
        listed, (gx, gy) = set(ends), ends[0]
        on_grid = [p for p in regions.end.points() if (p[0] - gx) % step == 0 and (p[1] - gy) % step == 0]
        found = sum(p in listed for p in on_grid) / len(on_grid) if on_grid else None
    return CrossCheck(
        starts=share(up.feasible_start_points, regions.start, 0, 0),
        starts_aligned=share(up.feasible_start_points, regions.start, *best),
        offset=best,
        ends=share(ends, regions.end, 0, 0),
        ends_found=found,
        end_miss_px=[regions.end.distance(*p) for p in ends if not regions.end.contains(*p)],
    )


def some(rng: random.Random, points: list[Point], count: int | None) -> list[Point]:
    """``count`` of ``points`` at random, or all of them (``None``)."""
    return list(points) if count is None else rng.sample(points, min(count, len(points)))


def boundary(value: str) -> int | None:
    return None if value == "all" else int(value)


async def attempt(editor: Editor, payload: DragPayload, start: Point, end: Point) -> bool:
    await page.set_up(editor, payload)
    before = await page.block_ids(editor)
    await page.drag(editor, start, end)
    connected, _ = await page.verify(editor, payload, before)
    return connected


async def measure(editor: Editor, task: DragTask, args: argparse.Namespace) -> TaskFigures:
    payload = task.payload(task.initial_project.read_bytes())
    await page.set_up(editor, payload)
    started = time.perf_counter()
    regions = await page.regions(editor, payload)
    figures = TaskFigures(task.id, time.perf_counter() - started, upstream=cross_check(task, regions))
    rng = random.Random(f"{args.seed}:{task.id}")
    rim, around = regions.end.boundary()
    inner = regions.end.points()
    samples: list[tuple[str, Point, Point, bool]] = []
    for points, expected in ((rim, True), (around, False)):
        samples += [("end", regions.fixed_start, p, expected) for p in some(rng, points, args.boundary)]
    samples += [("end", regions.fixed_start, p, True) for p in some(rng, inner, args.interior)]
    samples += [("end", regions.fixed_start, p, False) for p in exterior(regions.end, rng, args.interior)]
    aim = regions.end.deepest()
    offset = (aim[0] - regions.fixed_start[0], aim[1] - regions.fixed_start[1])
    rim, around = regions.start.boundary()
    for points, expected in ((rim, True), (around, False)):
        for p in some(rng, points, args.boundary):
            samples.append(("start", p, (p[0] + offset[0], p[1] + offset[1]), expected))
    for which, start, end, expected in samples:
        got = await attempt(editor, payload, start, end)
        figures.samples += 1
        figures.agreed += got == expected
        tally = figures.by_kind.setdefault(f"{which} {'inside' if expected else 'outside'}", [0, 0])
        tally[0] += got == expected
        tally[1] += 1
        if got != expected:
            figures.disagreements.append(f"{task.id} {which} {start}->{end}: region says {expected}, drag {got}")
    return figures


async def run(tasks: list[DragTask], args: argparse.Namespace) -> list[TaskFigures]:
    queue: asyncio.Queue[DragTask] = asyncio.Queue()
    for task in tasks:
        queue.put_nowait(task)
    results: list[TaskFigures] = []

    async def work(pool: EditorPool) -> None:
        while not queue.empty():
            task = queue.get_nowait()
            async with pool.editor() as editor:
                figures = await measure(editor, task, args)
            results.append(figures)
            print(
                f"  {task.id}: regions {figures.regions_s:.2f} s, agree {figures.agreed}/{figures.samples}", flush=True
            )

    async with BrowserSession(BrowserConfig()) as session, EditorPool(session, spare=0) as pool:
        await asyncio.gather(*(work(pool) for _ in range(args.editors)))
    return results


def report(name: str, results: list[TaskFigures]) -> None:
    times = [r.regions_s for r in results]
    samples, agreed = sum(r.samples for r in results), sum(r.agreed for r in results)
    print(f"\n{name}: {len(results)} task(s)")
    print(
        "  region computation per task: "
        f"median {statistics.median(times):.2f} s, mean {statistics.mean(times):.2f} s, max {max(times):.2f} s"
    )
    print(f"  real-drag agreement: {agreed}/{samples} = {100 * agreed / max(samples, 1):.2f}%")
    kinds: dict[str, list[int]] = {}
    for r in results:
        for kind, (good, total) in r.by_kind.items():
            tally = kinds.setdefault(kind, [0, 0])
            tally[0] += good
            tally[1] += total
    print("    " + ", ".join(f"{kind} {good}/{total}" for kind, (good, total) in sorted(kinds.items())))
    for line in [d for r in results for d in r.disagreements][:15]:
        print(f"    {line}")
    checked = [r.upstream for r in results if r.upstream is not None]
    if checked:
        offsets = sorted({c.offset for c in checked})
        found = [c.ends_found for c in checked if c.ends_found is not None]
        misses = [d for c in checked for d in c.end_miss_px]
        starts = 100 * statistics.mean(c.starts for c in checked)
        aligned = 100 * statistics.mean(c.starts_aligned for c in checked)
        ends = 100 * statistics.mean(c.ends for c in checked)
        shown = f"{offsets[:8]}{'...' if len(offsets) > 8 else ''}"
        print(f"  upstream cross-check over {len(checked)} task(s), means over tasks:")
        print(f"    upstream's feasible starts in our start region: {starts:.1f}% as they are, {aligned:.1f}% at each")
        print(f"      task's best offset (dx, dy in {shown})")
        line = f"    upstream's feasible ends (moved with the press) in our end region: {ends:.1f}%"
        if found:
            line += f"; of ours on their grid, upstream lists {100 * statistics.mean(found):.1f}% ({len(found)} tasks)"
        print(line)
        if misses:
            print(
                f"    upstream ends outside ours: {len(misses)}, median {statistics.median(misses):.1f} px "
                f"(max {max(misses):.1f}) from our end region"
            )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("suites", nargs="*", type=Path)
    parser.add_argument("--tasks", type=int, default=None, help="At most this many tasks per suite (a spread sample).")
    parser.add_argument("--per-kind", action="store_true", help="One task of each connection kind and source.")
    parser.add_argument("--ids", default=None, help="Comma-separated task ids (of any suite measured).")
    parser.add_argument(
        "--boundary", type=boundary, default=3, help="Boundary samples each side, per region ('all': every pixel)."
    )
    parser.add_argument("--interior", type=int, default=2, help="Random interior and exterior end samples.")
    parser.add_argument("--editors", type=int, default=2, help="Editors measuring at once.")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    suites = args.suites or [REPO / "drag-tasks", *([UPSTREAM] if UPSTREAM.is_dir() else [])]
    for root in suites:
        suite = load_drag_suite(root)
        tasks = list(suite.one_per_kind() if args.per_kind else suite.ready)
        if args.ids is not None:
            wanted = set(args.ids.split(","))
            tasks = [task for task in tasks if task.id in wanted]
        if args.tasks is not None and len(tasks) > args.tasks:
            step = len(tasks) / args.tasks
            tasks = [tasks[int(i * step)] for i in range(args.tasks)]
        print(f"{suite.name}: measuring {len(tasks)} task(s)", flush=True)
        report(suite.name, asyncio.run(run(tasks, args)))


if __name__ == "__main__":
    main()
