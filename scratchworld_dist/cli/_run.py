"""``scratchworld run CONFIG``: run (or resume) a sweep and print its report; ``scratchworld plan CONFIG``: the jobs
it would run, what is already decided, and what it may cost."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import click

from scratchworld_dist.cli._options import address_option, page_option, render_option, sweep_overrides, timing_option

if TYPE_CHECKING:
    from scratchworld_dist.sweep import SweepOverrides

EXIT_ERRORS = 1


@click.command("run", epilog="Example: scratchworld run configs/demo.yaml --tasks a,b --seeds 2 --out results/demo")
@click.argument("config_file", type=click.Path(dir_okay=False, path_type=Path))
@click.option("--out", help="Run directory, or a URL of one (s3://bucket/prefix; overrides output).")
@address_option
@click.option("--profile", type=click.Choice(["native", "upstream"]), help="Evaluation profile (overrides profile).")
@click.option("--clock", type=click.Choice(["virtual", "real"]), help="Evaluation clock (overrides clock).")
@render_option
@page_option
@timing_option
@click.option(
    "--model-cache",
    type=click.Path(file_okay=False, path_type=Path),
    help="Answer repeated model requests from this folder (overrides model_cache.dir).",
)
@click.option(
    "--probe/--no-probe",
    default=None,
    help="Call each model once before any job starts (overrides probe; default: when a model names api_key_env).",
)
@click.option(
    "--skip-broken-models",
    is_flag=True,
    help="Run the other models' jobs when the preflight finds a model broken (default: stop before any job).",
)
@click.option("--force", is_flag=True, help="Continue in a run directory that holds another sweep.")
@click.option(
    "--progress",
    type=click.Choice(["auto", "rich", "plain", "none"]),
    default="auto",
    show_default=True,
    help="A live line (rich), a line per interval and each error as it happens (plain: logs), or nothing; "
    "auto: live on a terminal, plain elsewhere.",
)
@click.option(
    "--progress-interval",
    type=click.FloatRange(min=0, min_open=True),
    default=30.0,
    show_default=True,
    help="Seconds between plain progress lines.",
)
@sweep_overrides
def run_command(
    config_file: Path,
    out: str | None,
    address: str | None,
    profile: str | None,
    clock: str | None,
    render: str | None,
    page: str | None,
    timing: str | None,
    model_cache: Path | None,
    probe: bool | None,
    skip_broken_models: bool,
    force: bool,
    progress: str,
    progress_interval: float,
    overrides: SweepOverrides,
) -> None:
    """Run the sweep in CONFIG_FILE; run it again to resume.

    Before any job starts, every model the jobs call is checked (its key and base URL set; by default
    one smallest call): a broken one stops the run, one line per model, with exit status 2. Prints the
    report (also saved as RUN_DIR/report.md) after the most frequent error message per class and model.
    Exits 1 when jobs are left without a verdict (errors after all retries; running again retries them).
    Every attempt is also an event in RUN_DIR/events.jsonl (docs/sweeps.md).
    """
    fields: dict[str, object] = {}
    if out is not None:
        fields["output"] = out if "://" in out else Path(out)
    if address is not None:
        fields["ray"] = {"address": address}
    if profile is not None:
        fields["profile"] = profile
    if clock is not None:
        fields["clock"] = clock
    if render is not None:
        fields["render"] = render
    if page is not None:
        fields["evaluation_page"] = page
    if timing is not None:
        fields["timing"] = timing
    if model_cache is not None:  # relative to the working directory, like --out; workers get it absolute
        fields["model_cache"] = {"dir": str(model_cache.resolve())}
    if probe is not None:
        fields["probe"] = probe
    from scratchworld_dist._console import make_console
    from scratchworld_dist.scheduling import ProgressOptions
    from scratchworld_dist.sweep import load_sweep_config

    config = load_sweep_config(config_file, fields, overrides)  # a bad config is refused before the heavy imports
    console = make_console(stderr=True)
    shown = ProgressOptions.model_validate({"mode": progress, "interval_s": progress_interval})
    from scratchworld_dist._run import run_sweep  # imports Ray: only for this command
    from scratchworld_dist.reports import digest_lines, report_runs, run_error_digest

    summary = run_sweep(config, force=force, console=console, skip_broken_models=skip_broken_models, progress=shown)
    outcomes = summary.outcomes
    left_out = f"; {summary.left_out} left out (broken models)" if summary.left_out else ""
    console.print(
        f"ran {summary.sent} attempt(s): passed {outcomes['passed']}, failed {outcomes['failed']}, "
        f"error {outcomes['error']} (retried {summary.retried}); {summary.already_decided} decided before{left_out}"
    )
    if summary.planned:
        for line in digest_lines(run_error_digest(summary.run_dir)):
            console.print(line, markup=False, soft_wrap=True)  # messages quote providers and scripts
    report, _ = report_runs([summary.run_dir], "md")  # its warnings are in its text
    (summary.run_dir / "report.md").write_text(report, encoding="utf-8")
    if config.remote_output() is not None:
        from scratchworld_dist.results.remote._sync import put_once

        note = put_once(config.remote_output(), "report.md", report.encode())
        if note is not None:
            console.print(note, markup=False)
    click.echo(report)
    if outcomes["error"]:
        raise click.exceptions.Exit(EXIT_ERRORS)


@click.command("plan", epilog="Example: scratchworld plan configs/demo.yaml --model openai/gpt-4o-mini --limit 5")
@click.argument("config_file", type=click.Path(dir_okay=False, path_type=Path))
@click.option("--out", type=click.Path(file_okay=False, path_type=Path), help="Run directory (overrides output).")
@click.option(
    "--tokens-from",
    multiple=True,
    type=click.Path(file_okay=False, path_type=Path),
    help="Measure tokens per step in this earlier run of the suite (repeatable; default: the run directory's own).",
)
@click.option("--json", "as_json", is_flag=True, help="Print the plan as JSON (PlanPreview; docs/sweeps.md).")
@sweep_overrides
def plan_command(
    config_file: Path, out: Path | None, tokens_from: tuple[Path, ...], as_json: bool, overrides: SweepOverrides
) -> None:
    """Show the jobs CONFIG_FILE would run (with the same overrides as ``run``), per model, agent and mode,
    each model's effective settings, and the estimated cost with its upper bound.

    Reads the suite and the run directory; starts nothing and writes nothing.
    """
    from scratchworld_dist._plan_preview import preview_plan
    from scratchworld_dist._plan_render import render_preview
    from scratchworld_dist.sweep import load_sweep_config

    config = load_sweep_config(config_file, {"output": out} if out is not None else None, overrides)
    preview = preview_plan(config, list(tokens_from))
    click.echo(preview.model_dump_json(indent=2) if as_json else render_preview(preview))
