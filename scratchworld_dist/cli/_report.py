"""``scratchworld report``: each benchmark's table over one or more run directories, and the diagnosis across them;
``scratchworld schemas OUT_DIR``: the JSON schemas of the reports as data, for readers in other languages."""

from __future__ import annotations

from pathlib import Path

import click

from scratchworld_dist.cli._output import emit
from scratchworld_dist.reports import FORMATS, ReportFormat, report_runs


@click.command("report")
@click.argument("run_dirs", nargs=-1, required=True, type=click.Path(path_type=Path))
@click.option("--format", "fmt", type=click.Choice(FORMATS), default="md", show_default=True, help="Output format.")
@click.option("--out", type=click.Path(dir_okay=False, path_type=Path), help="Write here instead of stdout.")
@click.option("--force", is_flag=True, help="Merge runs of different suites or harnesses anyway.")
def report_command(run_dirs: tuple[Path, ...], fmt: ReportFormat, out: Path | None, force: bool) -> None:
    """Summarize the results in RUN_DIR(s): SR per category, PSR, coverage, errors, cost.

    Several run directories merge into one report; they must share a suite and a harness
    (fingerprint) unless --force. Runs of the single-step drag benchmark get its own table
    (Pass@k, start and end accuracy and distances per drag type and setting) instead, and runs of
    the perception benchmark theirs (accuracy both ways per kind and tag, YES/NO confusion).
    Runs of several benchmarks are merged only within each benchmark: the report starts with a
    diagnosis table, one row per model (composite and primitive SR and their gap, drag Pass@1,
    perception accuracy), then each benchmark's own report.
    """
    text, warnings = report_runs(list(run_dirs), fmt, force=force)
    emit(text, out, warnings, f"{fmt} report")


@click.command("schemas")
@click.argument("out_dir", type=click.Path(file_okay=False, path_type=Path))
def schemas_command(out_dir: Path) -> None:
    """Write the JSON schema of each report ``report --format json`` writes into OUT_DIR (docs/schemas has them)."""
    from scratchworld_dist.reports import write_report_schemas

    for path in write_report_schemas(out_dir):
        click.echo(str(path))
