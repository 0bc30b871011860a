"""``scratchworld plan``'s text: the models' effective settings, one line per model, agent and mode with its
estimated tokens and cost, then the totals. A line's cost and the total agree: the total is unknown exactly when
a line that runs jobs has no price, and then says which."""

from __future__ import annotations

from scratchworld_dist._plan_preview import ModelSettings, PlanPreview


def render_preview(preview: PlanPreview) -> str:
    """The plan as plain text."""
    header = ("model", "agent", "mode", "jobs", "decided", "to run", "model calls (max)", "est. tokens in/out")
    header += ("est. cost", "at most")
    rows = [
        (
            line.model, line.agent, line.mode, str(line.jobs), str(line.decided), str(line.to_run),
            str(line.model_calls), f"{_tokens(line.cost.input_tokens)}/{_tokens(line.cost.output_tokens)}",
            _usd(line.cost.cost_usd), _usd(line.cost.max_cost_usd),
        )
        for line in preview.lines
    ]  # fmt: skip
    widths = [max(len(cell) for cell in column) for column in zip(header, *rows, strict=True)]
    table = [
        "  ".join(cell.ljust(width) for cell, width in zip(row, widths, strict=True)).rstrip()
        for row in (header, *rows)
    ]
    suite, totals = preview.suite, preview.totals
    sources = dict.fromkeys(line.cost.rates.source for line in preview.lines if line.cost.rates and line.to_run)
    notes = dict.fromkeys(line.cost.note for line in preview.lines if line.cost.note and line.to_run)
    priced = any(line.cost.cost_usd is not None for line in preview.lines if line.to_run and line.cost.rates)
    tags = " ".join(f"{key}={value}" for key, value in preview.tags.items())
    return "\n".join(
        [
            f"{preview.name}: benchmark {preview.benchmark}, {suite.tasks} item(s) of {suite.name}"
            f" -> {preview.run_dir}" + (f"  [tags {tags}]" if tags else ""),
            *preview.notices,
            *([f"warning: {preview.refusal}"] if preview.refusal else []),
            *(_model_line(model) for model in preview.models),
            *table,
            f"{totals.to_run} job(s) to run, {totals.decided} already decided; at most {totals.model_calls} model "
            f"call(s) ({_retries(preview.retries)})",
            f"estimated cost {_total(totals.cost_usd, totals.known_cost_usd, priced)} for "
            f"{_tokens(totals.input_tokens)} input and {_tokens(totals.output_tokens)} output tokens",
            *(f"  tokens per step: {source}" for source in sources),
            *(f"  {note}" for note in notes if note != "calls no model"),
            f"upper bound {_usd(totals.max_cost_usd)}: every attempt ({_retries(preview.retries)}) uses its whole step "
            "budget, every step fills the model's context and writes max_tokens",
        ]
    )


def _model_line(model: ModelSettings) -> str:
    """One model's effective settings; what its entry leaves unset is said as the default it gets."""
    if not model.called:
        return f"model {model.name} ({model.model}): not called by the agent"
    base = (
        model.api_base
        or (f"${model.api_base_env}" if model.api_base_env else None)
        or "LiteLLM's default for its provider"
    )
    key = f"${model.api_key_env}" if model.api_key_env else "LiteLLM's variable for its provider"
    parts = [
        f"temperature {model.temperature if model.temperature is not None else 'provider default'}",
        f"max_tokens {model.max_tokens if model.max_tokens is not None else 'provider default'}",
        f"endpoint {base}",
        f"key {key}",
        *(f"{name} {value}" for name, value in model.params.items()),
        f"probe {'on' if model.probed else 'off'}",
    ]
    price = model.price
    if price is not None and price.known:
        per_million = (price.input_usd_per_token or 0.0) * 1e6, (price.output_usd_per_token or 0.0) * 1e6
        parts.append(f"${per_million[0]:g}/${per_million[1]:g} per 1M tokens in/out")
        if price.max_input_tokens:
            parts.append(f"context {price.max_input_tokens:,} tokens")
    else:
        parts.append("no LiteLLM price")
    return f"model {model.name} ({model.model}): " + ", ".join(parts)


def _retries(retries: int) -> str:
    return f"each job retried up to {retries} time(s)" if retries else "no retries"


def _usd(value: float | None) -> str:
    return "unknown" if value is None else f"${value:,.4f}"


def _total(cost: float | None, known: float, priced: bool) -> str:
    if cost is not None:
        return _usd(cost)
    return f"unknown (${known:,.4f} for the lines with a price)" if priced else "unknown"


def _tokens(count: int) -> str:
    return f"{count / 1e6:.1f}M" if count >= 1e6 else f"{count / 1e3:.0f}k" if count >= 1e4 else str(count)
