"""Hand-made run directories for tests of reports and comparisons: job rows with plausible defaults, and the
drags and perception rows of those benchmarks' jobs."""

from __future__ import annotations

from collections.abc import Sequence
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from scratchworld_dist.kinds.drag import DragRow
from scratchworld_dist.kinds.perception import PerceptionRow
from scratchworld_dist.results import (
    JobRecord,
    JobRow,
    RegradeInfo,
    RunManifest,
    RunStore,
    TestRow,
    read_manifest,
    write_manifest,
)
from scratchworld_dist.suites import StabilityMarks
from scratchworld_dist.sweep import SuiteInfo
from workers.agent_api import AnswerFormat, ValueKind
from workers.contract import HarnessFingerprint
from workers.kinds.perception import score_reply

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


def drag_job(task: str, seed: int, outcome: str, **fields: Any) -> JobRow:
    """A drag job's row; ``fields`` override the defaults (job id is task/setting/seed/model)."""
    decided = outcome != "error"
    setting, model = fields.pop("setting", "baseline"), fields.pop("model", "gpt")
    values: dict[str, Any] = {
        "run_name": "drag",
        "model": model,
        "mode": "primitive",
        "task_id": task,
        "category": fields.pop("drag_type", "T1"),
        "task_hash": "h" + task,
        "seed": seed,
        "max_steps": 1,
        "harness_fingerprint": HARNESS.digest,
        "error_class": None if decided else "RateLimitError",
        "error_message": None if decided else "429",
        "eval_profile": None,
        "tests_passed": int(outcome == "passed"),
        "tests_total": int(decided),
        "psr": float(outcome == "passed") if decided else None,
        "steps": 1,
        "llm_calls": 1,
        "input_tokens": 10,
        "output_tokens": 5,
        "cost_usd": 0.01,
        "setting": setting,
    }
    agent = fields.get("agent", "llm")
    return job(f"{task}-{setting}-{seed}-{model}-{agent}", outcome, **(values | fields))


def drag_row(row: JobRow, *, start: float | None = 0.0, end: float | None = 0.0, parse: str = "ok") -> DragRow:
    """The drags row of a drag job's row: ``start``/``end`` are the distances (0 = inside, None = no point)."""
    return DragRow(
        job_id=row.job_id,
        attempt=row.attempt,
        task_id=row.task_id,
        drag_type=row.category,
        connection="next",
        source="canvas",
        setting=row.setting or "baseline",
        model=row.model,
        agent=row.agent,
        seed=row.seed,
        parse=parse,
        start_x=None if start is None else 100.0,
        start_y=None if start is None else 100.0,
        end_x=None if end is None else 200.0,
        end_y=None if end is None else 200.0,
        start_in_region=None if start is None else start == 0,
        start_error_px=start,
        end_in_region=None if end is None else end == 0,
        end_error_px=end,
        connected=row.outcome == "passed",
        observed="",
        fixed_start_x=100,
        fixed_start_y=100,
        gt_start_x=None,
        gt_start_y=None,
        start_area=400,
        end_area=100,
        regions_json='{"start": {"rows": [[100, 90, 109]]}, "fixed_start": [100, 100], "end": {"rows": []}}',
        reply="drag(...)",
        annotated=None,
    )


def drag_record(task: str, seed: int, outcome: str, *, start: float | None = 0.0, **fields: Any) -> JobRecord:
    """A drag job's record: its row and, unless it ended in error, its drags row (``start`` as in ``drag_row``)."""
    row = drag_job(task, seed, outcome, **fields)
    return JobRecord(job=row, drags=[] if outcome == "error" else [drag_row(row, start=start)])


def perception_record(
    item: str,
    expected: str,
    reply: str | None,
    *,
    kind: str = "connection",
    tag: str | None = None,
    value_kind: ValueKind | None = None,
    seed: int = 0,
    model: str = "gpt",
    agent: str = "llm",
    attempt: int = 1,
    error_class: str = "model_rate_limited",
    suite_hash: str = "suite1",
) -> JobRecord:
    """A perception job's record, ``reply`` scored both ways by the worker's own scoring; ``reply=None`` is a
    call that failed for good (an error row, no answer). A yes/no item unless ``value_kind`` is given."""
    answer_format: AnswerFormat = "yes_no" if value_kind is None else "value"
    fields: dict[str, Any] = {
        "run_name": "perception",
        "attempt": attempt,
        "model": model,
        "litellm_model": None if model == "-" else f"openai/{model}",
        "mode": "primitive",
        "agent": agent,
        "task_id": item,
        "category": kind,
        "task_hash": "h" + item,
        "seed": seed,
        "max_steps": 1,
        "eval_profile": None,
        "steps": 1,
        "llm_calls": int(model != "-"),
        "input_tokens": 50,
        "output_tokens": 2,
        "cost_usd": 0.001,
        "suite_hash": suite_hash,
    }
    job_id = f"p-{item}-{seed}-{model}-{agent}"
    if reply is None:
        error = {"error_class": error_class, "error_message": "gave up", "tests_total": 0, "tests_passed": 0}
        return JobRecord(job=job(job_id, "error", **(fields | error)))
    score = score_reply(reply, expected, answer_format, value_kind)
    outcome = "passed" if score.normalized else "failed"
    row = job(job_id, outcome, **(fields | {"tests_total": 1, "tests_passed": int(score.normalized)}))
    answer = PerceptionRow(
        job_id=job_id,
        attempt=attempt,
        item_id=item,
        question=f"A {kind} question about {item}?",
        kind=kind,
        tag=tag or f"{kind}_{expected.lower() if answer_format == 'yes_no' else value_kind}",
        answer_format=answer_format,
        value_kind=value_kind,
        model=model,
        agent=agent,
        seed=seed,
        expected=expected,
        reply=reply,
        extracted=score.extracted,
        parse=score.parse,
        strict_correct=score.strict,
        normalized_correct=score.normalized,
        screenshot=f"images/{item}.png",
    )
    return JobRecord(job=row, perception=[answer])


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
    stability: StabilityMarks | None = None,
    tags: dict[str, str] | None = None,
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
        else {"agent": "llm", "models": [{"model": "gpt"}], "episodes": {"modes": ["composite"]}, "seeds": [0]},
        config_hash="c",
        suite=SuiteInfo(name="ours", kind="native", root="/suite", hash=suite_hash, tasks=tasks, stability=stability),
        planned_jobs=planned,
        tags=tags or {},
    )
    write_manifest(run_dir, manifest)
    return run_dir


def job_with_tests(
    job_id: str, tests: dict[str, bool], stability: StabilityMarks | None = None, **fields: Any
) -> JobRecord:
    """A job's record with its test rows: ``tests`` maps each test's name to whether it passed (the outcome and
    counts follow from them), each marked unstable as ``stability`` says, as a run records them."""
    passed = sum(tests.values())
    row = job(
        job_id,
        "passed" if passed == len(tests) else "failed",
        **({"tests_passed": passed, "tests_total": len(tests), "psr": passed / len(tests)} | fields),
    )
    rows = [
        TestRow(
            job_id=row.job_id,
            attempt=row.attempt,
            task_id=row.task_id,
            test_index=index,
            name=name,
            passed=ok,
            error=None if ok else f"{name} failed",
            duration_ms=5.0,
            unstable=stability.is_unstable(row.task_id, name) if stability is not None else None,
        )
        for index, (name, ok) in enumerate(tests.items())
    ]
    return JobRecord(job=row, tests=rows)


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
