"""Trajectories in ATIF, the Agent Trajectory Interchange Format (Harbor's RFC 0001, v1.4).

The models follow the specification's tables field by field (required, optional, ``extra`` objects) and its
rules: step ids count from 1, only agent steps carry a model, reasoning, tool calls or metrics, and each
observation result names a tool call of its own step. No ATIF package is published on PyPI, so these models
are the schema ``docs/schemas/atif-v1.4.schema.json`` is generated from.

An episode maps onto it as: a user step with the task's instruction, then one agent step per action (the
model's raw reply as the message, the action as one tool call, what the environment answered as its
observation, the step's tokens and cost as metrics), and the job's tokens, cost and verdict in
``final_metrics``.
"""

from __future__ import annotations

import json
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field, JsonValue, model_validator

from scratchworld_dist.results import JobRow
from workers.contract import StepRecord

SCHEMA_VERSION = "ATIF-v1.4"


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid")


class AtifAgent(_Strict):
    name: str
    version: str
    model_name: str | None = None
    extra: dict[str, JsonValue] | None = None


class AtifToolCall(_Strict):
    tool_call_id: str
    function_name: str
    arguments: dict[str, JsonValue]


class AtifObservationResult(_Strict):
    source_call_id: str | None = None
    content: str | None = None


class AtifObservation(_Strict):
    results: list[AtifObservationResult]


class AtifMetrics(_Strict):
    prompt_tokens: int | None = Field(default=None, ge=0)
    completion_tokens: int | None = Field(default=None, ge=0)
    cached_tokens: int | None = Field(default=None, ge=0)
    cost_usd: float | None = Field(default=None, ge=0)
    extra: dict[str, JsonValue] | None = None


class AtifStep(_Strict):
    step_id: int = Field(ge=1)
    timestamp: str | None = None
    source: Literal["system", "user", "agent"]
    model_name: str | None = None
    message: str
    reasoning_content: str | None = None
    tool_calls: list[AtifToolCall] | None = None
    observation: AtifObservation | None = None
    metrics: AtifMetrics | None = None
    extra: dict[str, JsonValue] | None = None

    @model_validator(mode="after")
    def _agent_only_fields(self) -> AtifStep:
        if self.source != "agent":
            given = [f for f in ("model_name", "reasoning_content", "tool_calls", "metrics") if getattr(self, f)]
            if given:
                raise ValueError(f"a {self.source} step has agent-only field(s): {', '.join(given)}")
        calls = {call.tool_call_id for call in self.tool_calls or []}
        for result in self.observation.results if self.observation else []:
            if result.source_call_id is not None and result.source_call_id not in calls:
                raise ValueError(f"observation names tool call {result.source_call_id!r}, not one of its step's")
        return self


class AtifFinalMetrics(_Strict):
    total_prompt_tokens: int | None = None
    total_completion_tokens: int | None = None
    total_cached_tokens: int | None = None
    total_cost_usd: float | None = None
    total_steps: int | None = None
    extra: dict[str, JsonValue] | None = None


class AtifTrajectory(_Strict):
    schema_version: str = SCHEMA_VERSION
    session_id: str
    agent: AtifAgent
    steps: list[AtifStep]
    notes: str | None = None
    final_metrics: AtifFinalMetrics | None = None
    extra: dict[str, JsonValue] | None = None

    @model_validator(mode="after")
    def _sequential_steps(self) -> AtifTrajectory:
        ids = [step.step_id for step in self.steps]
        if ids != list(range(1, len(ids) + 1)):
            raise ValueError(f"step ids must count from 1 without gaps, not {ids[:5]}...")
        return self


def atif_trajectory(row: JobRow, steps: list[StepRecord], instruction: str | None, version: str) -> AtifTrajectory:
    """One attempt of an episode as an ATIF trajectory (``version``: this package's, the agent system's)."""
    atif_steps = [AtifStep(step_id=1, source="user", message=instruction or f"(task {row.task_id})")]
    for step in steps:
        call = AtifToolCall(tool_call_id=f"step-{step.index}", function_name=step.action, arguments=step.args)
        answer: dict[str, JsonValue] = {"ok": True, "data": step.data}
        if not step.ok:
            answer = {"ok": False, "error": step.error_code, "message": step.error_message}
        atif_steps.append(
            AtifStep(
                step_id=len(atif_steps) + 1,
                source="agent",
                model_name=row.litellm_model,
                message=step.reply or "",
                tool_calls=[call],
                observation=AtifObservation(
                    results=[AtifObservationResult(source_call_id=call.tool_call_id, content=json.dumps(answer))]
                ),
                metrics=AtifMetrics(
                    prompt_tokens=step.input_tokens, completion_tokens=step.output_tokens, cost_usd=step.cost_usd
                ),
                extra={"latency_s": step.latency_s, "llm_calls": step.llm_calls, "warnings": list(step.warnings)},
            )
        )
    verdict: dict[str, Any] = {
        "outcome": row.outcome, "tests_passed": row.tests_passed, "tests_total": row.tests_total, "psr": row.psr,
        "stop_reason": row.stop_reason, "error_class": row.error_class,
    }  # fmt: skip
    return AtifTrajectory(
        session_id=f"{row.job_id}-{row.attempt}",
        agent=AtifAgent(name=f"scratchworld-{row.agent}", version=version, model_name=row.litellm_model),
        steps=atif_steps,
        final_metrics=AtifFinalMetrics(
            total_prompt_tokens=row.input_tokens,
            total_completion_tokens=row.output_tokens,
            total_cost_usd=row.cost_usd,
            total_steps=len(atif_steps),
            extra=verdict,
        ),
        extra={
            "task_id": row.task_id,
            "category": row.category,
            "mode": row.mode,
            "seed": row.seed,
            "run_name": row.run_name,
            "benchmark": row.benchmark,
        },
    )
