"""``scratchworld report``: each benchmark's table over one or more run directories, and the diagnosis across them;
``scratchworld schemas OUT_DIR``: the JSON schemas of the reports as data, for readers in other languages."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import click

from scratchworld_dist.cli._options import RUN_DIR, report_format_option
from scratchworld_dist.cli._output import emit

if TYPE_CHECKING:
    from scratchworld_dist.reports import ReportFormat


@click.command(
    "report", epilog="Example: scratchworld report results/demo results/demo-2 --format html --out report.html"
)
@click.argument("run_dirs", nargs=-1, required=True, type=RUN_DIR)
@report_format_option
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
    from scratchworld_dist.reports import report_runs  # the statistics stack: when a report is made

    text, warnings = report_runs(list(run_dirs), fmt, force=force)
    emit(text, out, warnings, f"{fmt} report")


@click.command("schemas", epilog="Example: scratchworld schemas docs/schemas")
@click.argument("out_dir", type=click.Path(file_okay=False, path_type=Path))
def schemas_command(out_dir: Path) -> None:
    """Write the JSON schema of each report ``report --format json`` writes into OUT_DIR (docs/schemas has them)."""
    from scratchworld_dist.reports import write_report_schemas

    for path in write_report_schemas(out_dir):
        click.echo(str(path))
