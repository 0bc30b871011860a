"""What a sweep's jobs may cost before they run: an estimate and an upper bound per line (model, agent, mode).

The estimate is tokens per step times steps, priced by LiteLLM's price map (``litellm.model_cost``, through
``get_model_info``; a model's ``params`` may carry its own ``input_cost_per_token``/``output_cost_per_token``).
Tokens per step, steps per attempt and attempts per job are measured in run directories of the same suite and mode
(the plan's own run directory and those given with ``--tokens-from``: the same model's attempts when they have any,
else any model's), else the kind's documented per-mode default (``KindPlanning.token_rates``).

The upper bound assumes every attempt the run may make (``limits.retries`` retries of each job) uses its whole step
budget and every step fills the model's context window and writes ``max_tokens`` (else the model's output limit). A
model call the provider fails (a rate limit, an outage) is not billed, so the model-call retries (``llm.retry``) add
nothing to it.
"""

from __future__ import annotations

import os
import sys
from collections import defaultdict
from collections.abc import Sequence
from pathlib import Path
from types import ModuleType

from pydantic import BaseModel

from scratchworld_dist._errors import RunDirError
from scratchworld_dist.results import JobRow, RunStore, read_manifest
from scratchworld_dist.sweep import TokenRates
from workers.contract import ModelSpec


class ModelPrice(BaseModel):
    """What LiteLLM knows of a model: its prices per token and its limits (None: not in its map)."""

    input_usd_per_token: float | None
    output_usd_per_token: float | None
    max_input_tokens: int | None
    max_output_tokens: int | None

    @property
    def known(self) -> bool:
        return self.input_usd_per_token is not None and self.output_usd_per_token is not None


def _litellm() -> ModuleType:
    """LiteLLM with its bundled price map (else its import goes to the network); imported only when a model is
    priced (2-3 s)."""
    module = sys.modules.get("litellm")
    if module is None or getattr(module, "get_model_info", None) is None:
        os.environ.setdefault("LITELLM_LOCAL_MODEL_COST_MAP", "True")
        import litellm

        module = litellm
    return module


def model_price(spec: ModelSpec) -> ModelPrice:
    """LiteLLM's prices and limits of ``spec``'s model; the model's own ``*_cost_per_token`` params win."""
    try:
        info = dict(_litellm().get_model_info(spec.model))
    except Exception:  # LiteLLM raises a bare Exception for a model it has not mapped
        info = {}
    params = spec.params

    def number(key: str) -> float | None:
        value = params.get(key, info.get(key))
        if isinstance(value, bool) or not isinstance(value, int | float | str):
            return None
        try:
            return float(value)  # YAML reads 1e-6 as text
        except ValueError:
            return None

    def limit(key: str) -> int | None:
        value = info.get(key)
        return int(value) if isinstance(value, int | float) and value > 0 else None

    return ModelPrice(
        input_usd_per_token=number("input_cost_per_token"),
        output_usd_per_token=number("output_cost_per_token"),
        max_input_tokens=limit("max_input_tokens"),
        max_output_tokens=limit("max_output_tokens"),
    )


class MeasuredRuns:
    """Attempts that called a model in run directories of one suite, by mode and model, to measure tokens from."""

    def __init__(self, suite: str, run_dirs: Sequence[Path], own: Path, notes: list[str]) -> None:
        """``run_dirs``: directories the user named (one that is not a run is an error; one of another suite is
        said in ``notes`` and skipped); ``own``: the plan's run directory, used when it holds attempts."""
        self.rows: dict[str, list[tuple[Path, JobRow]]] = defaultdict(list)
        for run_dir in dict.fromkeys([*run_dirs, own]):
            manifest = read_manifest(run_dir) if run_dir.is_dir() else None
            if manifest is None:
                if run_dir != own:
                    raise RunDirError(f"--tokens-from {run_dir}: not a run directory (no manifest.json)")
                continue
            if manifest.suite.name != suite:
                notes.append(f"--tokens-from {run_dir}: a run of suite {manifest.suite.name}, not {suite}; not used")
                continue
            for row in RunStore(run_dir).job_rows():
                if row.llm_calls > 0 and row.steps > 0:
                    self.rows[row.mode].append((run_dir, row))

    def rates(self, mode: str, model: ModelSpec) -> TokenRates | None:
        """Tokens per step, steps per attempt and attempts per job of ``mode``: ``model``'s attempts (by its name
        or LiteLLM string) when there are any, else every model's; None when no attempt of ``mode`` called one."""
        found = self.rows.get(mode, [])
        same = [(d, r) for d, r in found if {model.name, model.model} & {r.model, r.litellm_model}]
        chosen = same or found
        if not chosen:
            return None
        rows = [row for _, row in chosen]
        steps = sum(row.steps for row in rows)
        jobs = {(run_dir, row.job_id) for run_dir, row in chosen}
        folders = ", ".join(sorted({str(run_dir) for run_dir, _ in chosen}))
        whose = f"{model.name}'s" if same else "all models'"
        return TokenRates(
            input_per_step=sum(row.input_tokens for row in rows) / steps,
            output_per_step=sum(row.output_tokens for row in rows) / steps,
            steps_per_attempt=steps / len(rows),
            attempts_per_job=len(rows) / len(jobs),
            source=f"measured: {len(rows)} {mode} attempt(s), {whose}, in {folders}",
        )


class LineCost(BaseModel):
    """A line's expected tokens and spend, and its upper bound."""

    input_tokens: int
    output_tokens: int
    cost_usd: float | None
    """Estimated spend (None: LiteLLM has no price for the model; see ``note``)."""

    max_cost_usd: float | None
    """The upper bound (None: no price, or no context limit known for the model)."""

    rates: TokenRates | None
    """The figures the estimate used (None: the line calls no model)."""

    note: str | None = None
    """Why the cost is unknown, or that the line calls no model."""


def line_cost(
    budgets: Sequence[int], spec: ModelSpec | None, rates: TokenRates | None, retries: int, price: ModelPrice | None
) -> LineCost:
    """The cost of jobs with step budgets ``budgets`` calling ``spec`` (None: they call no model)."""
    if spec is None or rates is None or price is None:
        return LineCost(
            input_tokens=0, output_tokens=0, cost_usd=0.0, max_cost_usd=0.0, rates=None, note="calls no model"
        )
    steps = sum(rates.steps(budget) * rates.attempts_per_job for budget in budgets)
    per_step_out = min(rates.output_per_step, spec.max_tokens or rates.output_per_step)  # max_tokens caps a reply
    tokens_in, tokens_out = round(steps * rates.input_per_step), round(steps * per_step_out)
    if not price.known:
        note = f"LiteLLM has no price for {spec.model} (give params input_cost_per_token, output_cost_per_token)"
        return LineCost(
            input_tokens=tokens_in, output_tokens=tokens_out, cost_usd=None, max_cost_usd=None, rates=rates, note=note
        )
    per_in, per_out = price.input_usd_per_token or 0.0, price.output_usd_per_token or 0.0
    cost = tokens_in * per_in + tokens_out * per_out
    most_out = spec.max_tokens or price.max_output_tokens
    bound = None
    if price.max_input_tokens is not None and most_out is not None:
        calls = sum(budgets) * (1 + retries)
        bound = calls * (price.max_input_tokens * per_in + most_out * per_out)
    note = None if bound is not None else f"LiteLLM knows no context limit of {spec.model}: no upper bound"
    return LineCost(
        input_tokens=tokens_in, output_tokens=tokens_out, cost_usd=cost, max_cost_usd=bound, rates=rates, note=note
    )
