"""Run directories whose suite has known test stability: a manifest with ``suite.stability`` and test rows
marked ``unstable`` as a run records them, for tests of reports, the viewer and ``compare --stable-only``."""

from __future__ import annotations

from pathlib import Path

from scratchworld_dist.results import JobRecord, JobRow
from scratchworld_dist.suites import StabilityMarks
from tests.support.run_dirs import job, job_with_tests, make_run

BEAT_NOTE = "unstable: phase changed it in 3 of 8 runs; passes at 30-60 fps"
HOSTILE = "<b>only</b> test"
HOSTILE_NOTE = 'unstable: lateness changed it in 2 of 4 runs; "<script>"'
MARKS = StabilityMarks(
    source="/suite/stability.json",
    made_on="2026-11-20",
    checked=["t1", "t2", "t3", "t4"],
    unstable={"t1": {"moves on the beat": BEAT_NOTE}, "t4": {HOSTILE: HOSTILE_NOTE}},
)
"""t1 has one unstable test beside a stable one; t4's only test is unstable; t2 and t3 have none."""

WEAK = {
    ("t1", 0): {"moves on the beat": False, "score shown": True},  # failed only on the unstable test
    ("t1", 1): {"moves on the beat": False, "score shown": False},  # failed on a stable test too
    ("t2", 0): {"a": True},
    ("t3", 0): {"a": False},
    ("t4", 0): {HOSTILE: False},  # no stable test: no verdict without the unstable ones
}
"""A system's tests by (task, seed): the stable-only verdicts differ from the recorded ones on t1 seed 0 and t4."""

STRONG = {key: dict.fromkeys(tests, True) for key, tests in WEAK.items()}
"""Another system that passes every test of the same jobs."""


def marked_run(
    run_dir: Path, tests: dict[tuple[str, int], dict[str, bool]], *, model: str, marks: StabilityMarks | None = MARKS
) -> Path:
    """A run of ``model`` with a job per (task, seed) of ``tests`` and an error job on t3 seed 1; ``marks=None``
    makes the same run as one whose suite has no stability data."""
    rows: list[JobRow | JobRecord] = [
        job_with_tests(f"{task}-{seed}-{model}", results, marks, task_id=task, seed=seed, model=model, task_hash=task)
        for (task, seed), results in tests.items()
    ]
    rows.append(job(f"t3-1-{model}", "error", task_id="t3", seed=1, model=model, task_hash="t3"))
    config = {"agent": "llm", "models": [{"model": model}], "episodes": {"modes": ["composite"]}, "seeds": [0, 1]}
    return make_run(run_dir, rows, planned=len(rows), tasks=4, config=config, stability=marks)
