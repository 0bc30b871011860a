"""``scratchworld schemas OUT_DIR``: the JSON schemas of the reports as data, for readers in other languages."""

from __future__ import annotations

from pathlib import Path

import click


@click.command("schemas")
@click.argument("out_dir", type=click.Path(file_okay=False, path_type=Path))
def schemas_command(out_dir: Path) -> None:
    """Write the JSON schema of each report ``report --format json`` writes into OUT_DIR (docs/schemas has them)."""
    from scratchworld_dist.reports import write_report_schemas

    for path in write_report_schemas(out_dir):
        click.echo(str(path))
