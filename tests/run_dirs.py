"""Hand-made run directories for tests of reports and comparisons: job rows with plausible defaults."""

from __future__ import annotations

from collections.abc import Sequence
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from scratchworld_dist.results import (
    JobRecord,
    JobRow,
    RegradeInfo,
    RunManifest,
    RunStore,
    SuiteInfo,
    read_manifest,
    write_manifest,
)
from workers.contract import HarnessFingerprint

T0 = datetime(2026, 1, 1, tzinfo=UTC)
PARTS = {"workers/_evaluation.py": "e1", "scratch-gui/clock.js": "c1", "package:litellm": "1.106.2"}
HARNESS = HarnessFingerprint(digest="aaaa111122223333", parts=PARTS)
OTHER_HARNESS = HarnessFingerprint(digest="bbbb444455556666", parts={**PARTS, "scratch-gui/clock.js": "c2"})


def job(job_id: str, outcome: str = "passed", **fields: Any) -> JobRow:
    """A job row with plausible defaults; ``fields`` override any of them."""
    decided = outcome != "error"
    values: dict[str, Any] = {
        "run_name": "sweep",
        "job_id": job_id,
        "attempt": 1,
        "model": "gpt",
        "litellm_model": "openai/gpt",
        "mode": "composite",
        "agent": "llm",
        "task_id": job_id,
        "category": "create",
        "task_hash": "t" + job_id,
        "suite_hash": "suite1",
        "seed": 0,
        "max_steps": 50,
        "harness_fingerprint": HARNESS.digest,
        "outcome": outcome,
        "error_class": None if decided else "EditorCrashedError",
        "error_message": None if decided else "page died",
        "eval_error_kind": None,
        "eval_profile": "native",
        "stop_reason": "done" if decided else "error",
        "tests_passed": 2 if outcome == "passed" else 0,
        "tests_total": 2 if decided else 0,
        "psr": (1.0 if outcome == "passed" else 0.0) if decided else None,
        "steps": 10,
        "llm_calls": 10,
        "input_tokens": 100,
        "output_tokens": 10,
        "cost_usd": 0.1,
        "episode_s": 1.0,
        "setup_s": 0.1,
        "agent_s": 0.8,
        "evaluation_s": 0.1,
        "started_at": T0,
        "finished_at": T0,
        "worker_node": None,
        "worker_host": None,
        "worker_pid": None,
        "worker_index": None,
        "artifact_dir": None,
    }
    values.update(fields)
    return JobRow(**values)


def make_run(
    run_dir: Path,
    rows: Sequence[JobRow | JobRecord],
    *,
    planned: int,
    tasks: int,
    config: dict[str, Any] | None = None,
    suite_hash: str = "suite1",
    harness: HarnessFingerprint = HARNESS,
    name: str = "sweep",
) -> Path:
    store = RunStore(run_dir)
    store.open_for_writing()
    for row in rows:  # a bare job row, or a record with its steps, tests and drags
        store.commit(row if isinstance(row, JobRecord) else JobRecord(job=row))
    store.close()
    manifest = RunManifest(
        run_name=name,
        schema_version=1,
        harness=harness,
        config=config
        if config is not None
        else {"agent": "llm", "models": [{"model": "gpt"}], "modes": ["composite"], "seeds": [0]},
        config_hash="c",
        suite=SuiteInfo(name="ours", kind="native", root="/suite", hash=suite_hash, tasks=tasks),
        planned_jobs=planned,
    )
    write_manifest(run_dir, manifest)
    return run_dir


def regrade_run(source: Path, out: Path, flips: set[str]) -> Path:
    """A hand-made regrade of ``source`` (three tasks): another suite, clock and harness; ``flips`` fail now."""
    current = {"suite_hash": "suite2", "harness_fingerprint": OTHER_HARNESS.digest, "eval_clock": "real"}
    rows = [
        job(
            f"r{i}",
            "failed" if f"t{i}" in flips else "passed",
            task_id=f"t{i}",
            task_hash=f"new{i}",
            regraded_from=f"t{i}",
            tests_passed=1 if f"t{i}" in flips else 2,
            tests_total=2,
            **current,
        )
        for i in range(3)
    ]
    make_run(out, rows, planned=3, tasks=3, suite_hash="suite2", harness=OTHER_HARNESS)
    manifest = read_manifest(out)
    assert manifest is not None
    suite = SuiteInfo(name="fixed", kind="native", root="/fixed", hash="suite2", tasks=3)
    info = RegradeInfo(
        source_run=str(source.resolve()),
        source_run_name="sweep",
        source_harness=HARNESS.digest,
        source_config_hash="c",
        suite=suite,
        profile="native",
        clock="real",
        regraded_jobs=3,
        without_project=0,
    )
    write_manifest(out, manifest.model_copy(update={"regrade": info}))
    return out
