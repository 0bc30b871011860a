"""An attempt's steps as the worker recorded them: its ``trajectory.jsonl`` artifact (observations, prompts,
replies), else the rows of the ``steps`` table, which keep the actions and their costs only."""

from __future__ import annotations

import json
from pathlib import Path

from pydantic import ValidationError

from scratchworld_dist._files import read_file
from scratchworld_dist.results._rows import JobRow, StepRow
from scratchworld_dist.results.remote._view import local_file
from workers.contract import StepRecord


def attempt_steps(run_dir: Path, row: JobRow, rows: list[StepRow]) -> tuple[list[StepRecord], str | None]:
    """An attempt's steps, whole from its trajectory artifact, else from its ``steps`` rows (without prompts,
    replies and observations), and a note when they are partial or missing."""
    if row.artifact_dir is not None:
        path = local_file(run_dir, f"{row.artifact_dir}/trajectory.jsonl")  # fetched now from a remote run
        if path.is_file():
            return _read_trajectory(path)
    steps = [_step_of(r) for r in sorted(rows, key=lambda r: r.step)]
    note = "no trajectory was kept for this attempt: steps come from the steps table" if steps else None
    return steps, note


def _read_trajectory(path: Path) -> tuple[list[StepRecord], str | None]:
    steps, bad = [], 0
    try:
        text = read_file(path, 256 * 2**20).decode("utf-8", errors="replace")
    except OSError as exc:
        return [], f"the trajectory cannot be read: {exc}"
    for line in text.splitlines():
        if not line.strip():
            continue
        try:
            steps.append(StepRecord.model_validate_json(line))
        except ValidationError:
            bad += 1
    return steps, f"{bad} line(s) of the trajectory are not steps and are left out" if bad else None


def _step_of(row: StepRow) -> StepRecord:
    try:
        args = json.loads(row.args_json)
    except ValueError:
        args = {"args_json": row.args_json}
    return StepRecord(
        index=row.step,
        action=row.action,
        args=args if isinstance(args, dict) else {"args": args},
        ok=row.ok,
        error_code=row.error_code,
        error_message=row.error_message,
        latency_s=row.latency_s,
        observation_s=row.observation_s,
        warnings=row.warnings.splitlines() if row.warnings else [],
        llm_calls=row.llm_calls,
        input_tokens=row.input_tokens,
        output_tokens=row.output_tokens,
        cost_usd=row.cost_usd,
    )
