"""Prints what the grader audit's exploration of each golden costs and shows, and whether it repeats.

    .venv/bin/python benchmarks/audit_exploration.py [--suite PATH] [--tasks a,b] [--repeats 2]

For each task of the suite (ours by default), its exploration plan (``scratchworld_dist.kinds.audit``: the
stimuli its golden's hats listen to, answer sets, seeds) is run on the golden, each episode ``--repeats`` times in
one editor pool, as the audit's workers run it. A line per task: episodes, the stimuli of one, the answer
domain, virtual seconds, VM frames, frames recorded, trace size, wall seconds per episode (median), the fields the
golden changes, and whether every repeat gave the same trace and outcome (determinism).
"""

from __future__ import annotations

import argparse
import asyncio
import io
import json
import statistics
import sys
import time
import zipfile
from pathlib import Path

from scratchworld_dist import load_suite
from scratchworld_dist.kinds.audit._declarations import suite_declarations
from scratchworld_dist.kinds.audit._exploration import exploration_plan
from workers.contract import ProjectLimits
from workers.editor import BrowserSession, EditorPool
from workers.evaluation import Evaluator
from workers.kinds.audit._golden_runs import explore
from workers.kinds.audit._vacuity import changed_fields

REPO = Path(__file__).resolve().parents[1]


async def measure(suite_dir: Path, task_ids: list[str] | None, repeats: int) -> int:
    suite = load_suite(suite_dir)
    declared = suite_declarations(suite)
    started = time.perf_counter()
    same_everywhere = True
    print(f"{'task':28} {'episodes':>8} {'stimuli':>7} {'domain':8} {'virtual s':>9} {'frames':>6} "
          f"{'recorded':>8} {'kB':>6} {'wall s/ep':>9} repeat  changes")  # fmt: skip
    async with BrowserSession() as session, EditorPool(session, spare=0) as pool:
        evaluator = Evaluator(session, pool)
        for task in suite.select(ids=task_ids):
            if task.golden_project is None:
                continue
            golden = task.golden_project.read_bytes()
            with zipfile.ZipFile(io.BytesIO(golden)) as archive:
                project = json.loads(archive.read("project.json"))
            entry = declared.get(task.id)
            plan = exploration_plan(project, task.instruction, entry.answers if entry else None)
            spec = task.evaluation_spec(clock="virtual")
            walls: list[float] = []
            changes: set[tuple[str, str]] = set()
            frames, recorded, chars, same = 0, 0, 0, True
            for episode in plan.episodes:
                runs = []
                for _ in range(repeats):
                    begun = time.perf_counter()
                    runs.append(await explore(evaluator, golden, spec, episode, ProjectLimits()))
                    walls.append(time.perf_counter() - begun)
                first = runs[0]
                if first.trace is None:
                    print(f"{task.id}: episode {episode.name!r} recorded no trace ({first.error})")
                    same = False
                    continue
                same &= all(r.trace == first.trace and r.outcome == first.outcome for r in runs[1:])
                frames += first.trace.steps
                recorded += len(first.trace.frames)
                chars += first.trace.chars
                changes |= changed_fields(first.trace)
            same_everywhere &= same
            span = sum(e.span_ms for e in plan.episodes) / 1000
            shown = ", ".join(sorted(f"{t}.{f}" for t, f in changes))
            print(f"{task.id[:28]:28} {len(plan.episodes):>8} {len(plan.episodes[0].stimuli):>7} "
                  f"{plan.answer_domain:8} {span:>9.0f} {frames:>6} {recorded:>8} {chars / 1000:>6.1f} "
                  f"{statistics.median(walls):>9.2f} {'same' if same else 'DIFFERS':6}  {shown[:90]}")  # fmt: skip
    print(f"\n{time.perf_counter() - started:.0f} s in all; every repeat the same: {same_everywhere}")
    return 0 if same_everywhere else 1


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--suite", type=Path, default=REPO / "tasks")
    parser.add_argument("--tasks", default=None, help="comma-separated task ids (default: all)")
    parser.add_argument("--repeats", type=int, default=2, help="runs of each episode (determinism)")
    args = parser.parse_args()
    ids = args.tasks.split(",") if args.tasks else None
    sys.exit(asyncio.run(measure(args.suite, ids, args.repeats)))


if __name__ == "__main__":
    main()
