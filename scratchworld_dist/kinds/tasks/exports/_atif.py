"""Trajectories in ATIF, the Agent Trajectory Interchange Format (Harbor's RFC 0001), built on the ``atif``
package's models (v1.8), which enforce the format's rules (step ids from 1, agent-only fields, observations that
name their own step's tool calls, ISO timestamps).

An episode maps onto it as the model's conversation, so a trajectory can be trained on:

- a ``system`` step with the system prompt (when the agent kept its prompts: the ``llm`` agents do);
- for each action, a ``user`` step with what the model was shown (the prompt's text; screenshots as image parts
  whose files are copied beside the trajectory, ``images/<sha256>.png``), or, for an agent without prompts, the
  task's instruction and the observation the environment made (composite text inline, a screenshot as a file);
- an ``agent`` step: the model's raw reply, its reasoning (what the provider returned as reasoning, else a
  ``<think>`` trace, else its ``Analysis:`` text), the action as one tool call, what the environment answered as
  its observation, the step's tokens and cost.

Each step's ``timestamp`` is wall-clock ISO 8601, when the worker began the step; ``extra.episode_clock_ms`` is
the time on the agent's page then (virtual clock, as the worker recorded it; real clock: the wall time since the
first observation). Runs recorded before workers kept a clock per step get both computed: the attempt's start
plus its setup and the latencies of the steps before; virtual: ``start_ms`` plus 50 ms and
``settle_ms + think_ms`` per action before, left out after a primitive drag, whose moves took time unrecorded.
``extra`` of the trajectory names the task, the suite and the run.
"""

from __future__ import annotations

import json
import re
import shutil
from datetime import UTC, datetime, timedelta
from pathlib import Path
from typing import Any

from atif import (
    Agent,
    ContentPart,
    FinalMetrics,
    ImageSource,
    Metrics,
    Observation,
    ObservationResult,
    Step,
    ToolCall,
    Trajectory,
)
from pydantic import JsonValue

from scratchworld_dist.results import JobRow, local_file
from scratchworld_dist.sweep import SuiteInfo
from workers.contract import EpisodeClock, StepObservation, StepRecord

SCHEMA_VERSION = "ATIF-v1.8"

ACTION_LEAD_MS = 50
"""Virtual page time before each action (``workers.kinds.tasks._pace.ACTION_LEAD_MS``; a test checks they agree)."""

DRAG_ACTIONS = frozenset({"drag_and_drop"})
"""Primitive actions whose moves pass virtual page time of their own (not recorded per step)."""

_THINK = re.compile(r"<think>(.*?)</think>", re.DOTALL)


def reasoning_of(reply: str | None) -> str | None:
    """The reasoning a reply carries: its ``<think>`` trace, else the text after ``Analysis:`` up to the action."""
    if not reply:
        return None
    traces = [trace.strip() for trace in _THINK.findall(reply) if trace.strip()]
    if traces:
        return "\n\n".join(traces)
    _, found, rest = reply.partition("Analysis:")
    return (rest.split("```", 1)[0].strip() or None) if found else None


class ImageFiles:
    """Screenshots a trajectory references, copied once into ``images/`` beside the trajectories of a run."""

    def __init__(self, run_dir: Path, artifact_dir: str | None, out_dir: Path) -> None:
        self.run_dir = run_dir
        self.sources = [f"{artifact_dir}/images"] if artifact_dir else []
        self.sources.append("images")  # images a run keeps once for many jobs
        self.out_dir = out_dir

    def part(self, sha256: str) -> ContentPart:
        """An image part naming the copied file, or a text part saying the screenshot was not kept."""
        if re.fullmatch(r"[0-9a-f]{64}", sha256):
            for folder in self.sources:
                source = local_file(self.run_dir, f"{folder}/{sha256}.png")  # a remote run's: fetched now
                if source.is_file():
                    target = self.out_dir / "images" / source.name
                    if not target.exists():
                        target.parent.mkdir(parents=True, exist_ok=True)
                        shutil.copyfile(source, target)
                    return ContentPart(
                        type="image", source=ImageSource(media_type="image/png", path=f"images/{source.name}")
                    )
        return ContentPart(type="text", text=f"[screenshot {sha256[:12]} was not kept]")


def _message(parts: list[ContentPart]) -> str | list[ContentPart]:
    """A plain string when the parts are all text, else the multimodal array."""
    if all(part.type == "text" for part in parts):
        return "\n\n".join(part.text or "" for part in parts)
    return parts


def _prompt_parts(message: JsonValue, images: ImageFiles) -> tuple[str, list[ContentPart]]:
    """A prompt message's role and its content as parts (``image_ref`` parts as image files)."""
    if not isinstance(message, dict):
        return "user", [ContentPart(type="text", text=json.dumps(message))]
    role, content = str(message.get("role", "user")), message.get("content")
    if isinstance(content, str):
        return role, [ContentPart(type="text", text=content)]
    parts = []
    for part in content if isinstance(content, list) else []:
        if isinstance(part, dict) and part.get("type") == "text":
            parts.append(ContentPart(type="text", text=str(part.get("text", ""))))
        elif isinstance(part, dict) and part.get("type") == "image_ref":
            parts.append(images.part(str(part.get("sha256", ""))))
    return role, parts


def _observation_parts(seen: StepObservation, images: ImageFiles) -> list[ContentPart]:
    """What the environment showed an agent that keeps no prompt: composite text, or a screenshot and its elements."""
    parts = [ContentPart(type="text", text=seen.text)] if seen.text is not None else []
    if seen.screenshot is not None:
        parts.append(images.part(seen.screenshot))
    if seen.elements:
        listing = "\n".join(
            f"{e.index} {e.type} {e.text!r} at ({e.x}, {e.y}) {e.width}x{e.height}" for e in seen.elements
        )
        parts.append(ContentPart(type="text", text=listing))
    return parts


def _iso(moment: datetime) -> str:
    return moment.isoformat(timespec="milliseconds").replace("+00:00", "Z")


def _episode_clock_ms(clock: EpisodeClock, index: int, waited_s: float, dragged: bool) -> float | None:
    if clock.mode == "real":
        return round(waited_s * 1000, 1)
    if dragged:
        return None
    return float(clock.start_ms + index * (ACTION_LEAD_MS + clock.step_ms))


def atif_trajectory(
    row: JobRow,
    steps: list[StepRecord],
    instruction: str | None,
    version: str,
    *,
    suite: SuiteInfo,
    clock: EpisodeClock,
    images: ImageFiles,
    tags: dict[str, str] | None = None,
) -> Trajectory:
    """One attempt of an episode as an ATIF trajectory (``version``: this package's, the agent system's; ``tags``:
    the run's, from ``--tag``)."""
    start = row.started_at + timedelta(seconds=row.setup_s)
    atif_steps: list[Step] = []

    def add(**fields: Any) -> None:
        atif_steps.append(Step(step_id=len(atif_steps) + 1, **fields))

    prompted = any(step.prompt for step in steps)
    system = [text for step in steps[:1] for m in step.prompt for role, text in [_prompt_text(m)] if role == "system"]
    if system:
        add(source="system", message="\n\n".join(system), timestamp=_iso(start))
    if not prompted:
        add(source="user", message=instruction or f"(task {row.task_id})", timestamp=_iso(start))
    waited, dragged = 0.0, False
    recorded = all(step.started_at is not None for step in steps)
    for step in steps:
        began = datetime.fromtimestamp(step.started_at, UTC) if step.started_at is not None else None
        when = _iso(began if recorded and began is not None else start + timedelta(seconds=waited))
        shown: list[ContentPart] = []
        for message in step.prompt:
            role, parts = _prompt_parts(message, images)
            if role != "system":
                shown += parts
        if not prompted and step.observation is not None:
            shown = _observation_parts(step.observation, images)
        if shown:
            add(source="user", message=_message(shown), timestamp=when)
        call = ToolCall(tool_call_id=f"step-{step.index}", function_name=step.action, arguments=step.args)
        answer: dict[str, JsonValue] = {"ok": True, "data": step.data}
        if not step.ok:
            answer = {"ok": False, "error": step.error_code, "message": step.error_message}
        called = step.llm_calls > 0
        extra: dict[str, Any] = {"latency_s": step.latency_s, "observation_s": step.observation_s}
        extra |= {"warnings": list(step.warnings), "llm_cache_hits": step.llm_cache_hits}
        episode_ms = _episode_clock_ms(clock, step.index, waited, dragged)
        if step.episode_clock_ms is not None:
            episode_ms = float(step.episode_clock_ms)
        if episode_ms is not None:
            extra |= {"episode_clock_ms": episode_ms, "episode_clock": clock.mode}
        add(
            source="agent",
            timestamp=when,
            model_name=row.litellm_model,
            message=step.reply or "",
            reasoning_content=(step.reasoning or reasoning_of(step.reply)) if called else None,
            tool_calls=[call],
            observation=Observation(
                results=[ObservationResult(source_call_id=call.tool_call_id, content=json.dumps(answer))]
            ),
            metrics=Metrics(
                prompt_tokens=step.input_tokens, completion_tokens=step.output_tokens, cost_usd=step.cost_usd
            )
            if called
            else None,
            llm_call_count=step.llm_calls,
            extra=extra,
        )
        waited += step.latency_s
        dragged = dragged or step.action in DRAG_ACTIONS
    verdict: dict[str, Any] = {
        "outcome": row.outcome, "tests_passed": row.tests_passed, "tests_total": row.tests_total, "psr": row.psr,
        "stop_reason": row.stop_reason, "error_class": row.error_class,
    }  # fmt: skip
    return Trajectory(
        schema_version=SCHEMA_VERSION,
        session_id=f"{row.job_id}-{row.attempt}",
        agent=Agent(name=f"scratchworld-{row.agent}", version=version, model_name=row.litellm_model),
        steps=atif_steps,
        final_metrics=FinalMetrics(
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
            "suite": {"name": suite.name, "kind": suite.kind, "hash": suite.hash},
            "run_name": row.run_name,
            "benchmark": row.benchmark,
            "started_at": _iso(row.started_at),
            "tags": dict(tags or {}),
            "timestamps": "wall clock: when the worker began each step"
            if recorded
            else "wall clock: the attempt's start, its setup and the latencies of the steps before",
        },
    )


def _prompt_text(message: JsonValue) -> tuple[str, str]:
    """A prompt message's role and its text parts joined (for the system prompt, which holds no image)."""
    if not isinstance(message, dict):
        return "user", json.dumps(message)
    content = message.get("content")
    if isinstance(content, list):
        content = "\n".join(str(p.get("text", "")) for p in content if isinstance(p, dict) and p.get("type") == "text")
    return str(message.get("role", "user")), str(content or "")


def trajectory_file_name(row: JobRow) -> str:
    """``<task>-<mode>-seed<k>-<job>-<attempt>.json``: the task first, so a folder lists a task's attempts together."""
    return f"{row.task_id}-{row.mode}-seed{row.seed}-{row.job_id}-{row.attempt}.json"
