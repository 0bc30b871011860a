"""``scratchworld compare``: two systems on the jobs both ran, with a paired interval and test."""

from __future__ import annotations

from pathlib import Path

import click

from scratchworld_dist.cli._output import emit
from scratchworld_dist.reports import FORMATS, ReportFormat, compare_runs, parse_selector, render_comparison


@click.command("compare")
@click.argument("system_a", metavar="RUN_A[:SYSTEM][@MODE]")
@click.argument("system_b", metavar="RUN_B[:SYSTEM][@MODE]")
@click.option("--format", "fmt", type=click.Choice(FORMATS), default="md", show_default=True, help="Output format.")
@click.option("--out", type=click.Path(dir_okay=False, path_type=Path), help="Write here instead of stdout.")
@click.option("--force", is_flag=True, help="Compare runs of different suites, harnesses or conditions anyway.")
@click.option("--resamples", type=click.IntRange(min=100), default=10_000, show_default=True, help="Bootstrap draws.")
@click.option("--seed", type=int, default=0, show_default=True, help="Seed of the bootstrap's draws.")
def compare_command(
    system_a: str, system_b: str, fmt: ReportFormat, out: Path | None, force: bool, resamples: int, seed: int
) -> None:
    """Compare system A with system B on the jobs both ran: SR and PSR differences with a
    paired bootstrap 95% interval over tasks, McNemar's exact test, and wins/losses per task.

    SYSTEM is a model label, an agent, or agent/model as `report` names its rows; it may be
    left out when the run holds one. @MODE pairs one mode with another (e.g. a model's
    composite against its primitive jobs); without it jobs are paired within each mode.
    Runs of different suites, harnesses, evaluation profiles or clocks are refused unless --force,
    except a regrade and its source (`scratchworld regrade`): for those the output names the
    regrade's conditions and lists the jobs whose verdict changed.
    """
    comparison = compare_runs(
        parse_selector(system_a), parse_selector(system_b), force=force, resamples=resamples, seed=seed
    )
    emit(render_comparison(comparison, fmt), out, comparison.warnings, f"{fmt} comparison")
