"""``scratchworld plan CONFIG``: the jobs a sweep would run, what is already decided, and what it may cost."""

from __future__ import annotations

from pathlib import Path

import click

from scratchworld_dist.cli._options import sweep_overrides
from scratchworld_dist.sweep import SweepOverrides, load_sweep_config


@click.command("plan")
@click.argument("config_file", type=click.Path(dir_okay=False, path_type=Path))
@click.option("--out", type=click.Path(file_okay=False, path_type=Path), help="Run directory (overrides output).")
@sweep_overrides
def plan_command(config_file: Path, out: Path | None, overrides: SweepOverrides) -> None:
    """Show the jobs CONFIG_FILE would run (with the same overrides as ``run``), per model, agent and mode.

    Reads the suite and the run directory; starts nothing and writes nothing.
    """
    from scratchworld_dist._plan_preview import preview_plan, render_preview

    config = load_sweep_config(config_file, {"output": out} if out is not None else None, overrides)
    click.echo(render_preview(preview_plan(config)))
