"""How many mutants and refactorings each golden of a suite gives, per operator, and what one costs to make.

Prints a row per task (mutants, refactorings, milliseconds per variant made), then the totals per operator.
Nothing is evaluated: this measures the audit's generators (``scratchworld_dist.kinds.audit.variants``) only.

Run: ``.venv/bin/python benchmarks/audit_variants.py [SUITE_DIR]`` (default: our ``tasks/``; an upstream
clone such as ``../shared/scratchworld-upstream`` works too).
"""

from __future__ import annotations

import io
import json
import sys
import time
import zipfile
from collections import Counter
from pathlib import Path

from scratchworld_dist import SuiteError
from scratchworld_dist.kinds.audit.variants import OPERATORS, REFACTORINGS, enumerate_mutants, enumerate_refactorings
from scratchworld_dist.suites import load_suite

REPO = Path(__file__).resolve().parents[1]


def main() -> int:
    try:
        suite = load_suite(Path(sys.argv[1]) if len(sys.argv) > 1 else REPO / "tasks")
    except SuiteError as exc:
        print(f"cannot load the suite: {exc}", file=sys.stderr)
        return 2
    mutants: Counter[str] = Counter()
    refactorings: Counter[str] = Counter()
    spent = {"mutants": 0.0, "refactorings": 0.0}
    seen: set[Path] = set()
    print(f"{'task':48} {'mutants':>8} {'ms each':>8} {'refact.':>8} {'ms each':>8}")
    for task in suite.tasks:
        if task.golden_project is None or task.golden_project in seen:
            continue  # upstream's debug tasks share one golden per starter project
        seen.add(task.golden_project)
        with zipfile.ZipFile(io.BytesIO(task.golden_project.read_bytes())) as archive:
            project = json.loads(archive.read("project.json"))
        start = time.perf_counter()
        made = enumerate_mutants(project)
        middle = time.perf_counter()
        refactored = enumerate_refactorings(project)
        end = time.perf_counter()
        spent["mutants"] += middle - start
        spent["refactorings"] += end - middle
        mutants.update(m.operator for m in made)
        refactorings.update(r.operator for r in refactored)
        print(
            f"{task.category + '/' + task.id:48} {len(made):8} {_ms(middle - start, len(made)):>8} "
            f"{len(refactored):8} {_ms(end - middle, len(refactored)):>8}"
        )
    total_m, total_r = sum(mutants.values()), sum(refactorings.values())
    print(f"\n{len(seen)} goldens: {total_m} mutants ({_ms(spent['mutants'], total_m)} ms each), ", end="")
    print(f"{total_r} refactorings ({_ms(spent['refactorings'], total_r)} ms each)")
    for name in OPERATORS:
        print(f"  mutant {name:22} {mutants[name]:6}")
    for name in REFACTORINGS:
        print(f"  refactoring {name:17} {refactorings[name]:6}")
    return 0


def _ms(seconds: float, count: int) -> str:
    return f"{1000 * seconds / count:.1f}" if count else "-"


if __name__ == "__main__":
    sys.exit(main())
