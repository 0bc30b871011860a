"""Prints what observable traces say of a grader audit's variants: equivalent mutants, holes, brittle tests.

    .venv/bin/python benchmarks/audit_traces.py [--suite PATH] [--tasks a,b] [--mutants-per-task 6] [--seed 0]

For each task of the suite (ours by default), its golden, every refactoring and a sample of mutants
(``scratchworld_dist.kinds.audit.variants``) are evaluated with the observable trace recorded (one editor pool, one
``Math.random`` seed), and each variant's trace is compared with the golden's (``first_difference``).
A line per variant worth a look: a mutant that passes every test (equivalent when the traces are
equal, a grader hole otherwise, with the first difference as evidence) and a refactoring that fails
one (brittle; a trace that differs there usually means the script drove it otherwise, e.g. by looking
a variable up by name). Then the counts per kind, verdict and trace equality.
"""

from __future__ import annotations

import argparse
import asyncio
import io
import json
import sys
import time
import zipfile
from collections import Counter
from pathlib import Path

from scratchworld_dist import load_suite
from scratchworld_dist.kinds.audit.variants import ProgramVariant, enumerate_refactorings, sample_mutants
from scratchworld_dist.sb3 import Sb3Archive
from workers.contract import EvalResult
from workers.editor import BrowserSession, EditorPool
from workers.evaluation import Evaluator, first_difference

REPO = Path(__file__).resolve().parents[1]


def verdict(result: EvalResult) -> str:
    return result.error.kind if result.error else ("pass" if result.success else "fail")


async def audit(suite_dir: Path, task_ids: list[str] | None, mutants: int, seed: int) -> int:
    tasks = load_suite(suite_dir).select(ids=task_ids)
    counts: Counter[tuple[str, str, str]] = Counter()
    started = time.perf_counter()
    async with BrowserSession() as session, EditorPool(session, spare=0) as pool:
        evaluator = Evaluator(session, pool)
        for task in tasks:
            if task.golden_project is None:
                continue
            golden = task.golden_project.read_bytes()
            with zipfile.ZipFile(io.BytesIO(golden)) as archive:
                project = json.loads(archive.read("project.json"))
            spec = task.evaluation_spec()
            reference = await evaluator.evaluate_traced(golden, spec, random_seed=seed)
            if reference.trace is None or not reference.result.success:
                print(f"{task.id}: the golden does not pass ({verdict(reference.result)}); skipped")
                continue
            assets = Sb3Archive(golden)
            variants: list[tuple[str, ProgramVariant]] = [("refactoring", v) for v in enumerate_refactorings(project)]
            variants += [("mutant", v) for v in sample_mutants(project, mutants, seed)]
            for kind, variant in variants:
                run = await evaluator.evaluate_traced(assets.with_project(variant.project), spec, random_seed=seed)
                found = first_difference(reference.trace, run.trace) if run.trace else None
                seen = "no trace" if run.trace is None else ("equal" if found is None else "differs")
                counts[(kind, verdict(run.result), seen)] += 1
                worth = (kind == "mutant" and run.result.success) or (kind == "refactoring" and not run.result.success)
                if worth:
                    evidence = "traces equal" if found is None else found.describe()[:160]
                    print(f"{task.id[:26]:26} {kind:11} {variant.operator:20} {verdict(run.result):5} {evidence}")
    print(f"\n{'kind':11} {'verdict':14} {'trace':8} count")
    for (kind, result, seen), count in sorted(counts.items()):
        print(f"{kind:11} {result:14} {seen:8} {count}")
    print(f"{sum(counts.values())} variant(s) of {len(tasks)} task(s) in {time.perf_counter() - started:.0f} s")
    return 0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--suite", type=Path, default=REPO / "tasks")
    parser.add_argument("--tasks", default=None, help="comma-separated task ids (default: all)")
    parser.add_argument("--mutants-per-task", type=int, default=6)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    ids = args.tasks.split(",") if args.tasks else None
    sys.exit(asyncio.run(audit(args.suite, ids, max(0, args.mutants_per_task), args.seed)))


if __name__ == "__main__":
    main()
