"""``scratchworld export RUN_DIR... --format F --out DIR``: task-episode runs for other tools."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import click

from scratchworld_dist.cli._options import RUN_FOLDER

if TYPE_CHECKING:
    from scratchworld_dist.kinds.tasks.exports import ExportFormat

FORMATS = ("leaderboard", "upstream-submission", "atif")
"""``EXPORT_FORMATS``, spelled here so the help does not load the exports (a test checks the two agree)."""


@click.command("export", epilog="Example: scratchworld export results/demo --format atif --out exports/demo")
@click.argument("run_dirs", nargs=-1, required=True, type=RUN_FOLDER)
@click.option(
    "--format",
    "fmt",
    type=click.Choice(FORMATS),
    required=True,
    help="leaderboard (CSV, JSON), upstream-submission (JSONL per agent/model/mode/seed), atif (one file per job).",
)
@click.option("--out", type=click.Path(file_okay=False, path_type=Path), required=True, help="Folder to write into.")
@click.option("--force", is_flag=True, help="Merge runs of other suites or harnesses into one leaderboard.")
def export_command(run_dirs: tuple[Path, ...], fmt: ExportFormat, out: Path, force: bool) -> None:
    """Write RUN_DIRS (task-episode runs) in FORMAT under OUT, each job at its counted attempt."""
    from scratchworld_dist.kinds.tasks.exports import export_runs

    summary = export_runs(list(run_dirs), fmt, out, force=force)
    for warning in summary.warnings:
        click.echo(f"warning: {warning}", err=True)
    click.echo(f"wrote {len(summary.files)} file(s) under {out}")
