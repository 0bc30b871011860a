"""``scratchworld status RUN_DIR``: how far a run got, read from its files alone."""

from __future__ import annotations

from pathlib import Path

import click
from rich.markup import escape

from scratchworld_dist._console import make_console
from scratchworld_dist.cli._options import RUN_FOLDER


@click.command("status", epilog="Example: scratchworld status results/demo")
@click.argument("run_dir", type=RUN_FOLDER)
@click.option("--json", "as_json", is_flag=True, help="Print the progress as JSON (RunStatus; docs/sweeps.md).")
def status_command(run_dir: Path, as_json: bool) -> None:
    """Print the progress of the run in RUN_DIR without running anything."""
    from scratchworld_dist._run_status import run_status  # pyarrow: when it runs
    from scratchworld_dist.results import require_manifest
    from scratchworld_dist.results.remote._view import shown_location

    manifest = require_manifest(run_dir)
    status = run_status(run_dir, manifest)
    if as_json:
        click.echo(status.model_dump_json(indent=2))
        return
    console = make_console()
    console.print(f"[bold]{escape(manifest.run_name)}[/bold]  {escape(shown_location(run_dir))}")
    harness = status.harness or "-"
    console.print(
        f"suite {manifest.suite.name} ({manifest.suite.tasks} tasks, hash {manifest.suite.hash}); harness {harness}",
        markup=False,
    )
    if status.tags:
        console.print("tags: " + " ".join(f"{key}={value}" for key, value in status.tags.items()), markup=False)
    console.print(
        f"{status.decided}/{status.planned_jobs} decided: passed {status.passed}, failed {status.failed}; "
        f"error {status.error}; not yet run {status.not_yet_run}; attempts recorded {status.attempts}"
    )
    if status.errors:
        console.print("errors: " + ", ".join(f"{kind} {count}" for kind, count in status.errors.items()), markup=False)
    for number, session in enumerate(manifest.sessions, start=1):
        end = session.finished_at.isoformat(timespec="seconds") if session.finished_at else "did not finish"
        console.print(
            f"session {number}: {session.started_at.isoformat(timespec='seconds')} -> {end} "
            f"on {session.host} (pid {session.pid}), {session.planned} job(s) to run"
        )
