"""Prints how fast a real grader audit evaluates variants: per second, per variant, and what tracing costs.

    .venv/bin/python benchmarks/audit_evaluation.py [--suite tasks] [--tasks a,b] [--mutants-per-task 3]
        [--refactorings-per-task 1] [--seed 0] [--out DIR]

Runs the audit as ``scratchworld audit`` does (a sweep of kind ``audit`` on a private local Ray, in this
process): each selected task's golden, and the capped mutants and refactorings of it. Then, from the run
directory's rows and the time each result reached the driver:

- wall: from the sweep's start to its end (Ray, the workers and their browsers start within it);
  evaluating: from the first job's start to the last result's arrival;
- variants per second: the evaluated jobs (goldens included: each is one evaluation of a project) over
  the wall, and over the evaluating phase;
- per variant: the verdict's evaluation (a row's ``evaluation_s``) and the whole job on its worker (its
  start to its result's arrival: the verdict, then, for a misjudged variant, the two traced runs);
- traced: the variants the tests misjudged (a mutant that passed, a refactoring that failed), traced with
  their golden; a row times only its verdict's evaluation, so a traced job's tracing is the time from its
  row's end to its result's arrival, less what that takes for jobs not traced (the result's way back,
  median); its share is of the jobs' whole time on their workers.

Keep it small on a shared machine: the default caps make 5 jobs per task of our suite.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path
from typing import Any

from _audit_arrivals import arrivals
from rich.console import Console

from scratchworld_dist._run import run_sweep
from scratchworld_dist.results import RunStore
from scratchworld_dist.sweep import SweepConfig, sweep_config_from

REPO = Path(__file__).resolve().parents[1]


def config(args: argparse.Namespace, out: Path) -> SweepConfig:
    section: dict[str, Any] = {"seed": args.seed, "mutants_per_task": args.mutants_per_task}
    section["refactorings_per_task"] = args.refactorings_per_task
    data: dict[str, Any] = {"name": "audit-evaluation", "benchmark": "audit", "suite": str(args.suite)}
    data |= {"audit": section, "output": str(out)}
    if args.tasks:
        data["tasks"] = {"ids": args.tasks.split(",")}
    return sweep_config_from(data, Path.cwd())


def measure(args: argparse.Namespace, out: Path) -> int:
    sweep = config(args, out)
    began = time.time()
    with arrivals() as arrived:
        summary = run_sweep(sweep, console=Console(quiet=True))
    ended = time.time()
    store = RunStore(summary.run_dir)
    jobs = {(j["job_id"], j["attempt"]): j for j in store.read_table("jobs").to_pylist()}
    audits = {(a["job_id"], a["attempt"]): a for a in store.read_table("audits").to_pylist()}
    done = [key for key in jobs if key in arrived]
    if not done:
        print(f"no job ran (the run directory {summary.run_dir} may hold them all already: use a new --out)")
        return 1
    first = min(jobs[key]["started_at"].timestamp() for key in done)
    evaluating = max(arrived[key] for key in done) - first
    whole = {key: arrived[key] - jobs[key]["started_at"].timestamp() for key in done}
    back = {key: arrived[key] - jobs[key]["finished_at"].timestamp() for key in done}
    traced = [key for key in done if audits[key]["observed"] is not None]
    untraced = [back[key] for key in done if key not in traced] or [0.0]
    tracing = sum(max(0.0, back[key] - statistics.median(untraced)) for key in traced)
    kinds = Counter(audits[key]["variant"] for key in done)
    verdicts = Counter(audits[key]["verdict"] for key in done)
    evaluations = [jobs[key]["evaluation_s"] for key in done]
    wall = ended - began

    counts = ", ".join(f"{n} {k}" for k, n in kinds.items())
    print(f"audit of {args.suite} ({summary.run_dir}): {len(done)} jobs, {counts}")
    print(f"wall {wall:.1f} s (start-up {first - began:.1f} s: Ray, workers, browsers); evaluating {evaluating:.1f} s")
    rates = f"{len(done) / wall:.2f} over the wall, {len(done) / evaluating:.2f} evaluating"
    print(f"variants evaluated per second: {rates}")
    print(
        f"per variant: verdict's evaluation mean {statistics.mean(evaluations):.2f} s "
        f"(median {statistics.median(evaluations):.2f}); whole job on its worker mean "
        f"{statistics.mean(whole.values()):.2f} s (median {statistics.median(whole.values()):.2f})"
    )
    share = tracing / sum(whole.values()) if whole else 0.0
    print(
        f"traced: {len(traced)} of {len(done)} (misjudged: "
        f"{sum(v in ('hole', 'equivalent', 'survived', 'brittle') for v in (audits[k]['verdict'] for k in done))}); "
        f"tracing {tracing:.1f} s of {sum(whole.values()):.1f} s on the workers ({100 * share:.1f}%)"
    )
    print("verdicts: " + ", ".join(f"{verdict} {count}" for verdict, count in verdicts.most_common()))
    errors = verdicts.get("error", 0)
    return 1 if errors else 0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--suite", type=Path, default=REPO / "tasks")
    parser.add_argument("--tasks", default=None, help="comma-separated task ids (default: all)")
    parser.add_argument("--mutants-per-task", type=int, default=3)
    parser.add_argument("--refactorings-per-task", type=int, default=1)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", type=Path, default=None, help="run directory to keep (default: a temporary one)")
    args = parser.parse_args()
    if args.out is not None:
        sys.exit(measure(args, args.out))
    with tempfile.TemporaryDirectory(prefix="audit-evaluation-") as tmp:
        sys.exit(measure(args, Path(tmp) / "run"))


if __name__ == "__main__":
    main()
