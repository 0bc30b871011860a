"""Upstream's leaderboard submission: one JSONL file of executed actions per agent, model, mode and seed.

Upstream's ``curate_submit.py`` writes, for a result directory (one model, mode and agent), one line per task
with ``take`` (the task), ``type`` (its category), ``mode``, ``interactions`` (``turn`` and the executed
``action``: ``api`` and ``args``) and where the line came from (``source_interaction_log``,
``source_task_dir``). Ours are the same lines, one file per agent, model, mode and seed (upstream ran one
seed), from each job's counted attempt; the action is what the environment executed, with its arguments as
recorded (pixel positions in primitive mode, block references in composite mode).
"""

from __future__ import annotations

import re

from pydantic import BaseModel, JsonValue

from scratchworld_dist.results import JobRow
from scratchworld_dist.sweep import NO_MODEL
from workers.contract import StepRecord


class SubmittedAction(BaseModel):
    api: str
    args: dict[str, JsonValue]


class SubmittedTurn(BaseModel):
    turn: int
    action: SubmittedAction


class SubmissionLine(BaseModel):
    take: str
    type: str
    mode: str
    interactions: list[SubmittedTurn]
    source_interaction_log: str | None
    source_task_dir: str | None


def submission_file_name(row: JobRow) -> str:
    """``<model>_<mode>_<agent>_seed<k>.jsonl``, upstream's result-directory naming (``/ \\ -`` and spaces as ``_``)."""
    model = re.sub(r"[/\\\- ]", "_", row.litellm_model or ("none" if row.model == NO_MODEL else row.model))
    return f"{model}_{row.mode}_{row.agent}_seed{row.seed}.jsonl"


def submission_line(row: JobRow, steps: list[StepRecord]) -> SubmissionLine:
    """One task's line: its executed actions in order, turns counted from 1."""
    turns = [
        SubmittedTurn(turn=number, action=SubmittedAction(api=step.action, args=step.args))
        for number, step in enumerate(steps, start=1)
    ]
    log = f"{row.artifact_dir}/trajectory.jsonl" if row.artifact_dir is not None else None
    return SubmissionLine(
        take=row.task_id, type=row.category, mode=row.mode, interactions=turns, source_interaction_log=log,
        source_task_dir=row.artifact_dir,
    )  # fmt: skip
