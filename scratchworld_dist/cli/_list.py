"""``scratchworld list tasks|agents|models|benchmarks``: what there is to run, as a table or as JSON.

Each subcommand imports what it reads when it runs (a suite, the agent registry, LiteLLM's price map), so
listing the commands stays light.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import click

json_option = click.option("--json", "as_json", is_flag=True, help="Print JSON (a list of objects) instead.")

PER_MILLION = 1_000_000


def _show(rows: list[dict[str, Any]], as_json: bool, columns: list[str]) -> None:
    """``rows`` as JSON, or as aligned text columns (a missing value as ``-``) with a header."""
    if as_json:
        click.echo(json.dumps(rows, indent=2))
        return
    cells = [[("-" if row.get(c) is None else str(row[c])) for c in columns] for row in rows]
    widths = [max([len(c), *(len(line[i]) for line in cells)]) for i, c in enumerate(columns)]
    for line in [columns, *cells]:
        click.echo("  ".join(cell.ljust(width) for cell, width in zip(line, widths, strict=True)).rstrip())


@click.group("list", epilog="Example: scratchworld list models --provider openai --json")
def list_group() -> None:
    """List the tasks of a suite, the agents, the models (a config's, LiteLLM's priced ones) or the benchmarks."""


@list_group.command("tasks", epilog="Example: scratchworld list tasks ../scratchworld-upstream --task-list 15_tasks")
@click.argument("suite_dir", type=click.Path(file_okay=False, path_type=Path))
@click.option("--task-list", help="Upstream task list, e.g. all_tasks or 15_tasks.")
@json_option
def tasks_command(suite_dir: Path, task_list: str | None, as_json: bool) -> None:
    """The tasks of the suite in SUITE_DIR: id, category, whether a golden project and a trajectory ship."""
    from scratchworld_dist.suites import load_suite

    suite = load_suite(suite_dir, task_list=task_list)
    rows = [
        {
            "id": task.id,
            "category": task.category,
            "golden": task.golden_project is not None,
            "trajectory": task.golden_trajectory is not None,
        }
        for task in suite.tasks
    ]
    _show(rows, as_json, ["id", "category", "golden", "trajectory"])


@list_group.command("agents", epilog="Example: scratchworld list agents --benchmark drag")
@click.option("--benchmark", help="Only this benchmark's agents (default: every installed benchmark's).")
@json_option
def agents_command(benchmark: str | None, as_json: bool) -> None:
    """The agents registered for each benchmark (a plugin's too), by the names a sweep config uses."""
    from scratchworld_dist.kinds import UnknownKindError, job_kind, kind_names
    from workers.agent_api import AgentUnavailableError, registered_agents

    try:
        kinds = [job_kind(benchmark).name] if benchmark is not None else kind_names()
    except UnknownKindError as exc:
        raise click.BadParameter(str(exc), param_hint="--benchmark") from None
    rows = []
    for kind in kinds:
        try:
            rows += [{"benchmark": kind, "agent": agent} for agent in registered_agents(kind)]
        except AgentUnavailableError:  # a benchmark without agents (the grader audit): nothing to list
            if benchmark is not None:
                raise
    _show(rows, as_json, ["benchmark", "agent"])


@list_group.command(
    "models",
    epilog="Example: scratchworld list models configs/local-llm.yaml; scratchworld list models --provider openai",
)
@click.argument("config_file", required=False, type=click.Path(dir_okay=False, path_type=Path))
@click.option("--provider", help="LiteLLM's known models of this provider (openai, anthropic...) with their prices.")
@json_option
def models_command(config_file: Path | None, provider: str | None, as_json: bool) -> None:
    """The models CONFIG_FILE names (with the price LiteLLM knows for each), or with --provider the models
    LiteLLM knows for that provider: USD per million input and output tokens, and the context limit."""
    if config_file is None and provider is None:
        raise click.UsageError("give a CONFIG_FILE, --provider, or both")
    prices = _price_map()
    rows: list[dict[str, Any]] = []
    if config_file is not None:
        from scratchworld_dist.sweep import load_sweep_config

        for model in load_sweep_config(config_file).models:
            rows.append({"source": str(config_file), "name": model.name or model.model, **_priced(model.model, prices)})
    if provider is not None:
        known = sorted(name for name, entry in prices.items() if entry.get("litellm_provider") == provider)
        if not known:
            providers = sorted({str(e.get("litellm_provider")) for e in prices.values() if e.get("litellm_provider")})
            raise click.BadParameter(f"LiteLLM knows no model of {provider!r}; providers: {', '.join(providers)}")
        rows += [{"source": "litellm", "name": name, **_priced(name, prices)} for name in known]
    _show(rows, as_json, ["source", "name", "model", "input_usd_per_mtok", "output_usd_per_mtok", "context_tokens"])


def _price_map() -> dict[str, dict[str, Any]]:
    """LiteLLM's price and context map (its bundled copy: listing never goes to the network)."""
    import asyncio

    from workers.llm import load_litellm

    litellm = asyncio.run(load_litellm())
    return {name: entry for name, entry in litellm.model_cost.items() if isinstance(entry, dict)}


def _priced(model: str, prices: dict[str, dict[str, Any]]) -> dict[str, Any]:
    """What LiteLLM's map says of ``model`` (``provider/name`` found by its name too); None where it says nothing."""
    entry = prices.get(model) or prices.get(model.split("/", 1)[-1]) or {}

    def per_million(key: str) -> float | None:
        value = entry.get(key)
        return round(value * PER_MILLION, 6) if isinstance(value, int | float) else None

    context = entry.get("max_input_tokens") or entry.get("max_tokens")
    return {
        "model": model,
        "input_usd_per_mtok": per_million("input_cost_per_token"),
        "output_usd_per_mtok": per_million("output_cost_per_token"),
        "context_tokens": context if isinstance(context, int) else None,
    }


@list_group.command("benchmarks", epilog="Example: scratchworld list benchmarks --json")
@json_option
def benchmarks_command(as_json: bool) -> None:
    """The installed benchmarks (a plugin's too): the name a config's ``benchmark:`` takes, and what it runs."""
    from scratchworld_dist.kinds import job_kinds

    rows = [{"benchmark": kind.name, "title": kind.title, "browser": kind.needs_browser} for kind in job_kinds()]
    _show(rows, as_json, ["benchmark", "title", "browser"])
