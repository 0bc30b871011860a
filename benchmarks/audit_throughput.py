"""Prints the upstream grader audit's throughput: variants per second, wall time and the verdicts behind them.

    .venv/bin/python benchmarks/audit_throughput.py [SUITE_DIR] [--every 5 | --tasks a,b | --every 1]
        [--mutants-per-task 15] [--refactorings-per-task N] [--seed 0] [--full-kills] [--out DIR]
        [--compare RUN_DIR]

Runs the audit as ``scratchworld audit`` does (a sweep of kind ``audit`` on a private local Ray, in this
process, the suite's own clock, profile and timing: for an upstream clone, virtual, upstream, calibrated) on the
tasks of SUITE_DIR (default ``../shared/scratchworld-upstream``) whose evaluation scripts exist, as docs/audits.md's
upstream audit: 15 mutants per task (seed 0) and every refactoring. The sample: every ``--every``-th of those tasks
in the suite's order (categories in turn; ``--every 1``: all 67), or ``--tasks``. ``--full-kills`` runs every test
of every mutant (``audit.stop_at_first_kill: false``); by default a mutant's tests stop at the first that fails it.

Prints the machine's load (1-minute average) before and after, the jobs and their kinds, the wall time (Ray,
workers and browsers started within it) and the evaluating phase (first job's start to the last result), variants
per second over each, the verdict counts, the mutants stopped early, and the jobs' evaluation time (a row's
``evaluation_s``: the verdict's evaluation, not the traces of a misjudged variant) per kind and per task (the
slowest). ``--compare`` matches this run's variants with another run directory's (by task and variant id) and
prints every verdict, observation or evidence that differs: an audit sped up must judge every variant as before.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import tempfile
import time
from collections import Counter, defaultdict
from itertools import pairwise
from pathlib import Path
from typing import Any

from _audit_arrivals import arrivals
from rich.console import Console

from scratchworld_dist._run import run_sweep
from scratchworld_dist.results import RunStore
from scratchworld_dist.sweep import SweepConfig, sweep_config_from

REPO = Path(__file__).resolve().parents[1]
SCRIPTS = Path("scratch-bench-api/api/evaluation_scripts")
CATEGORIES = ("create", "debug", "extend", "compute")


def scripted_tasks(suite: Path) -> dict[str, list[str]]:
    """The suite's task files whose evaluation scripts exist, by category, in the suite's order."""
    found: dict[str, list[str]] = {}
    for category in CATEGORIES:
        for path in sorted((suite / "tasks" / category).glob("*.json")):
            if (suite / SCRIPTS / f"{path.stem}.js").is_file():
                found.setdefault(category, []).append(path.name)
    return found


def sample(tasks: dict[str, list[str]], every: int) -> list[str]:
    """Every ``every``-th task id, in the suite's order."""
    ordered = [name.removesuffix(".json") for category in CATEGORIES for name in tasks.get(category, [])]
    return ordered[::every]


def config(args: argparse.Namespace, task_list: Path, ids: list[str], out: Path) -> SweepConfig:
    section: dict[str, Any] = {"seed": args.seed, "mutants_per_task": args.mutants_per_task}
    section["refactorings_per_task"] = args.refactorings_per_task
    if args.full_kills:
        section["stop_at_first_kill"] = False
    data: dict[str, Any] = {"name": "audit-throughput", "benchmark": "audit", "suite": str(args.suite)}
    data |= {"tasks": {"task_list": str(task_list), "ids": ids}, "audit": section, "output": str(out)}
    return sweep_config_from(data, Path.cwd())


def worker_time(jobs: list[dict[str, Any]], arrived: dict[tuple[str, int], float]) -> tuple[float, float, float]:
    """Where the workers' time went: the verdicts' evaluations, what came after a verdict until its result reached
    the driver (a misjudged variant's traces, the worker's load, the way back), and from a result's arrival to
    the worker's next job (the driver's commit, the next job's way there)."""
    verdicts = sum(j["evaluation_s"] for j in jobs)
    after = sum(arrived[(j["job_id"], j["attempt"])] - j["finished_at"].timestamp() for j in jobs)
    between = 0.0
    by_worker: dict[object, list[dict[str, Any]]] = defaultdict(list)
    for job in jobs:
        by_worker[job["worker_pid"]].append(job)
    for mine in by_worker.values():
        mine.sort(key=lambda j: j["started_at"])
        for done, following in pairwise(mine):
            between += following["started_at"].timestamp() - arrived[(done["job_id"], done["attempt"])]
    return verdicts, after, between


def rows_by_variant(run_dir: Path) -> dict[tuple[str, str, str], dict[str, Any]]:
    """The last attempt's audit row of each variant, by (task, variant kind, variant id)."""
    rows: dict[tuple[str, str, str], dict[str, Any]] = {}
    for row in sorted(RunStore(run_dir).read_table("audits").to_pylist(), key=lambda r: r["attempt"]):
        rows[(row["task_id"], row["variant"], row["variant_id"])] = row
    return rows


def compare(ours: Path, theirs: Path) -> int:
    """Prints the variants judged otherwise than in ``theirs``; returns how many."""
    mine, other = rows_by_variant(ours), rows_by_variant(theirs)
    shared = sorted(set(mine) & set(other))
    differ = 0
    for key in shared:
        a, b = mine[key], other[key]
        fields = [f for f in ("verdict", "observed", "evidence") if a.get(f) != b.get(f)]
        if fields:
            differ += 1
            changes = "; ".join(f"{f} {b.get(f)!r} -> {a.get(f)!r}" for f in fields)
            failing = f"failing tests {b['failing_tests']} -> {a['failing_tests']}"
            print(f"  differs: {key[0]} {key[1]} {key[2]} ({a['description']}): {changes}; {failing}")
    print(f"compared with {theirs}: {len(shared)} variants in both, {differ} judged otherwise")
    return differ


def measure(args: argparse.Namespace, out: Path, task_list: Path, ids: list[str]) -> int:
    sweep = config(args, task_list, ids, out)
    load_before = os.getloadavg()[0]
    began = time.time()
    with arrivals() as arrived:
        summary = run_sweep(sweep, console=Console(quiet=True))
    wall = time.time() - began
    load_after = os.getloadavg()[0]
    store = RunStore(summary.run_dir)
    jobs = [j for j in store.read_table("jobs").to_pylist() if (j["job_id"], j["attempt"]) in arrived]
    if not jobs:
        print(f"no job ran (the run directory {summary.run_dir} may hold them all already: use a new --out)")
        return 1
    audits = {(a["job_id"], a["attempt"]): a for a in store.read_table("audits").to_pylist()}
    rows = [audits[(j["job_id"], j["attempt"])] for j in jobs]
    first = min(j["started_at"].timestamp() for j in jobs)
    last = max(j["finished_at"].timestamp() for j in jobs)
    kinds = Counter(r["variant"] for r in rows)
    verdicts = Counter(r["verdict"] for r in rows)
    stopped = sum(1 for r in rows if r.get("stopped_at") is not None)

    print(f"suite {args.suite}: {len(ids)} task(s): {', '.join(ids)}")
    print(f"load average (1 min): {load_before:.2f} before, {load_after:.2f} after, on {os.cpu_count()} cores")
    print(f"{len(jobs)} jobs: " + ", ".join(f"{n} {k}" for k, n in sorted(kinds.items())) + f" -> {summary.run_dir}")
    print(f"wall {wall:.1f} s (start-up {first - began:.1f} s); evaluating {last - first:.1f} s")
    print(f"variants per second: {len(jobs) / wall:.3f} over the wall, {len(jobs) / (last - first):.3f} evaluating")
    print("verdicts: " + ", ".join(f"{v} {n}" for v, n in verdicts.most_common()))
    print(f"mutants stopped at their first failing test: {stopped} of {kinds.get('mutant', 0)}")
    evaluation = [j["evaluation_s"] for j in jobs]
    print(
        f"evaluation per job: mean {statistics.mean(evaluation):.2f} s, median {statistics.median(evaluation):.2f} s, "
        f"sum {sum(evaluation):.0f} s"
    )
    verdicts_s, after_s, between_s = worker_time(jobs, arrived)
    print(
        f"workers' time: verdicts {verdicts_s:.0f} s, after a verdict (traces, the way back) {after_s:.0f} s, "
        f"between a result and the next job {between_s:.0f} s"
    )
    by_kind: dict[str, list[float]] = defaultdict(list)
    by_task: dict[str, float] = defaultdict(float)
    for job, row in zip(jobs, rows, strict=True):
        by_kind[f"{row['variant']} {row['verdict']}"].append(job["evaluation_s"])
        by_task[job["task_id"]] += job["evaluation_s"]
    for kind, times in sorted(by_kind.items()):
        print(f"  {kind}: {len(times)} jobs, {sum(times):.0f} s, mean {statistics.mean(times):.2f} s")
    slowest = sorted(by_task.items(), key=lambda item: -item[1])[:8]
    print("slowest tasks (evaluation s): " + ", ".join(f"{task} {s:.0f}" for task, s in slowest))
    differ = compare(summary.run_dir, args.compare) if args.compare else 0
    return 1 if verdicts.get("error", 0) or differ else 0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("suite", nargs="?", type=Path, default=REPO.parent / "shared" / "scratchworld-upstream")
    parser.add_argument("--every", type=int, default=5, help="every N-th task with a script (1: all)")
    parser.add_argument("--tasks", default=None, help="comma-separated task ids (instead of --every)")
    parser.add_argument("--mutants-per-task", type=int, default=15)
    parser.add_argument("--refactorings-per-task", type=int, default=None, help="default: every refactoring")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--full-kills", action="store_true", help="run every test of a killed mutant")
    parser.add_argument("--out", type=Path, default=None, help="run directory to keep (default: a temporary one)")
    parser.add_argument("--compare", type=Path, default=None, help="another run directory of the same audit")
    args = parser.parse_args()
    if not (args.suite / SCRIPTS).is_dir():
        sys.exit(f"{args.suite} is not an upstream clone with evaluation scripts")
    with tempfile.TemporaryDirectory(prefix="audit-throughput-") as tmp:
        # Beside a run directory kept: its manifest names the list, and a resume reads it again.
        task_list = args.out.with_name(f"{args.out.name}.tasks.json") if args.out else Path(tmp) / "tasks.json"
        tasks = scripted_tasks(args.suite)
        task_list.parent.mkdir(parents=True, exist_ok=True)
        task_list.write_text(json.dumps(tasks))
        ids = args.tasks.split(",") if args.tasks else sample(tasks, args.every)
        sys.exit(measure(args, args.out or Path(tmp) / "run", task_list, ids))


if __name__ == "__main__":
    main()
