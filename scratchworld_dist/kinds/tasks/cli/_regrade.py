"""``scratchworld regrade RUN_DIR --out NEW_RUN_DIR``: a run's final projects evaluated again, no agent re-run."""

from __future__ import annotations

from pathlib import Path

import click

from scratchworld_dist._console import make_console
from scratchworld_dist.cli._options import RUN_FOLDER, address_option, page_option, render_option
from workers.contract import EvaluationClock, EvaluationPage, EvaluationProfile, EvaluationRender

EXIT_ERRORS = 1


@click.command(
    "regrade", epilog="Example: scratchworld regrade results/demo --out results/demo-fixed --suite tasks-fixed"
)
@click.argument("run_dir", type=RUN_FOLDER)
@click.option("--out", required=True, type=click.Path(file_okay=False, path_type=Path), help="The new run directory.")
@click.option("--suite", type=click.Path(file_okay=False, path_type=Path), help="Suite (default: the source's).")
@click.option(
    "--profile", type=click.Choice(["native", "upstream"]), help="Evaluation profile (default: the source's)."
)
@click.option("--clock", type=click.Choice(["virtual", "real"]), help="Evaluation clock (default: the source's).")
@render_option
@page_option
@address_option
@click.option("--force", is_flag=True, help="Continue in an --out that holds another regrade or run.")
def regrade_command(
    run_dir: Path,
    out: Path,
    suite: Path | None,
    profile: EvaluationProfile | None,
    clock: EvaluationClock | None,
    render: EvaluationRender | None,
    page: EvaluationPage | None,
    address: str | None,
    force: bool,
) -> None:
    """Evaluate every final project stored in RUN_DIR again, under another suite (e.g. a fixed
    evaluation script), profile or clock, into a new run directory; run it again to resume.

    Prints how many verdicts changed and the report (also saved as OUT/report.md); `compare
    RUN_DIR OUT` lists the changed jobs. Exits 1 when regrades are left without a verdict.
    """
    from scratchworld_dist.kinds.tasks.regrade import run_regrade  # imports Ray: only for this command
    from scratchworld_dist.reports import report_runs

    console = make_console(stderr=True)
    summary = run_regrade(
        run_dir,
        out,
        suite=suite,
        profile=profile,
        clock=clock,
        render=render,
        page=page,
        address=address,
        force=force,
        console=console,
    )
    outcomes = summary.outcomes
    console.print(
        f"regraded {summary.planned} job(s): sent {summary.sent} attempt(s) (passed {outcomes['passed']}, "
        f"failed {outcomes['failed']}, error {outcomes['error']}, retried {summary.retried}); "
        f"{summary.already_decided} decided before"
        + (f"; {summary.elapsed_s:.1f} s, {summary.sent / summary.elapsed_s:.2f} jobs/s" if summary.sent else "")
    )
    console.print(f"verdicts: {summary.unchanged} unchanged, {len(summary.changed)} changed")
    for change in summary.changed:
        console.print(
            f"  {change.task_id} seed {change.seed} {change.mode}: {change.before} -> {change.after} "
            f"(tests {change.tests_before} -> {change.tests_after})",
            markup=False,
        )
    skipped = summary.without_project
    if skipped:
        shown = "; ".join(skipped[:20]) + (f"; and {len(skipped) - 20} more" if len(skipped) > 20 else "")
        console.print(f"skipped {len(skipped)} job(s) that stored no final project: {shown}", markup=False)
    report, _ = report_runs([summary.run_dir], "md")
    (summary.run_dir / "report.md").write_text(report, encoding="utf-8")
    click.echo(report)
    if outcomes["error"]:
        raise click.exceptions.Exit(EXIT_ERRORS)
