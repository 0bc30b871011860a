"""``scratchworld status RUN_DIR``: how far a run got, read from its files alone."""

from __future__ import annotations

from collections import Counter
from pathlib import Path

import click
from rich.markup import escape

from scratchworld_dist._console import make_console


@click.command("status", epilog="Example: scratchworld status results/demo")
@click.argument("run_dir", type=click.Path(file_okay=False, path_type=Path))
def status_command(run_dir: Path) -> None:
    """Print the progress of the run in RUN_DIR without running anything."""
    from scratchworld_dist.results import RunStore, effective_rows, require_manifest  # pyarrow: when it runs

    manifest = require_manifest(run_dir)
    rows = manifest.current_rows(RunStore(run_dir).job_rows())
    effective = list(effective_rows(rows))
    outcomes = Counter(r.outcome for r in effective)
    errors = Counter(r.error_class or "?" for r in effective if r.outcome == "error")
    decided = outcomes["passed"] + outcomes["failed"]
    missing = max(manifest.planned_jobs - len(effective), 0)
    console = make_console()
    console.print(f"[bold]{escape(manifest.run_name)}[/bold]  {escape(str(run_dir))}")
    harness = manifest.harness.digest if manifest.harness else "-"
    console.print(
        f"suite {manifest.suite.name} ({manifest.suite.tasks} tasks, hash {manifest.suite.hash}); harness {harness}",
        markup=False,
    )
    console.print(
        f"{decided}/{manifest.planned_jobs} decided: passed {outcomes['passed']}, failed {outcomes['failed']}; "
        f"error {outcomes['error']}; not yet run {missing}; attempts recorded {len(rows)}"
    )
    if errors:
        console.print("errors: " + ", ".join(f"{kind} {count}" for kind, count in errors.most_common()), markup=False)
    for number, session in enumerate(manifest.sessions, start=1):
        end = session.finished_at.isoformat(timespec="seconds") if session.finished_at else "did not finish"
        console.print(
            f"session {number}: {session.started_at.isoformat(timespec='seconds')} -> {end} "
            f"on {session.host} (pid {session.pid}), {session.planned} job(s) to run"
        )
