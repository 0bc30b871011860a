"""``scratchworld run CONFIG``: run (or resume) a sweep and print its report."""

from __future__ import annotations

from pathlib import Path

import click

from scratchworld_dist._console import make_console
from scratchworld_dist.cli._render_option import render_option
from scratchworld_dist.cli._timing_option import timing_option
from scratchworld_dist.reports import report_runs
from scratchworld_dist.sweep import load_sweep_config

EXIT_ERRORS = 1


@click.command("run")
@click.argument("config_file", type=click.Path(dir_okay=False, path_type=Path))
@click.option("--out", type=click.Path(file_okay=False, path_type=Path), help="Run directory (overrides output).")
@click.option("--address", help="Ray cluster to join (default: RAY_ADDRESS, else a private local Ray).")
@click.option("--profile", type=click.Choice(["native", "upstream"]), help="Evaluation profile (overrides profile).")
@click.option("--clock", type=click.Choice(["virtual", "real"]), help="Evaluation clock (overrides clock).")
@render_option
@timing_option
@click.option(
    "--model-cache",
    type=click.Path(file_okay=False, path_type=Path),
    help="Answer repeated model requests from this folder (overrides model_cache.dir).",
)
@click.option("--force", is_flag=True, help="Continue in a run directory that holds another sweep.")
def run_command(
    config_file: Path,
    out: Path | None,
    address: str | None,
    profile: str | None,
    clock: str | None,
    render: str | None,
    timing: str | None,
    model_cache: Path | None,
    force: bool,
) -> None:
    """Run the sweep in CONFIG_FILE; run it again to resume.

    Prints the report (also saved as RUN_DIR/report.md). Exits 1 when jobs are left without a
    verdict (errors after all retries; running again retries them).
    """
    overrides: dict[str, object] = {}
    if out is not None:
        overrides["output"] = out
    if address is not None:
        overrides["ray"] = {"address": address}
    if profile is not None:
        overrides["profile"] = profile
    if clock is not None:
        overrides["clock"] = clock
    if render is not None:
        overrides["render"] = render
    if timing is not None:
        overrides["timing"] = timing
    if model_cache is not None:  # relative to the working directory, like --out; workers get it absolute
        overrides["model_cache"] = {"dir": str(model_cache.resolve())}
    from scratchworld_dist._run import run_sweep  # imports Ray: only for this command

    config = load_sweep_config(config_file, overrides)
    console = make_console(stderr=True)
    summary = run_sweep(config, force=force, console=console)
    outcomes = summary.outcomes
    console.print(
        f"ran {summary.sent} attempt(s): passed {outcomes['passed']}, failed {outcomes['failed']}, "
        f"error {outcomes['error']} (retried {summary.retried}); {summary.already_decided} decided before"
    )
    report, _ = report_runs([summary.run_dir], "md")  # its warnings are in its text
    (summary.run_dir / "report.md").write_text(report, encoding="utf-8")
    click.echo(report)
    if outcomes["error"]:
        raise click.exceptions.Exit(EXIT_ERRORS)
