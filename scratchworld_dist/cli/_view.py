"""``scratchworld view``: browse run directories locally, or export them as a static site."""

from __future__ import annotations

import asyncio
from pathlib import Path

import click

from scratchworld_dist.cli._options import RUN_DIR


@click.command("view", epilog="Example: scratchworld view results/demo --export site/")
@click.argument("run_dirs", nargs=-1, required=True, type=RUN_DIR)
@click.option("--port", type=click.IntRange(0, 65535), default=0, show_default=True, help="Port (0: a free one).")
@click.option(
    "--export",
    "export_dir",
    type=click.Path(path_type=Path, file_okay=False),
    help="Write a static copy here instead of serving (opens from file://; no network needed).",
)
def view_command(run_dirs: tuple[Path, ...], port: int, export_dir: Path | None) -> None:
    """Show RUN_DIRS in a browser: the report with plots, the jobs, each job's steps and tests.

    Serves on 127.0.0.1 (the URL is printed; nothing is opened) until interrupted. Pages are read
    at each request, so a run in progress shows its new jobs on refresh.
    """
    from scratchworld_dist.viewer import ViewerSite, export_site

    site = ViewerSite(list(run_dirs))
    if export_dir is not None:
        summary = export_site(site, export_dir)
        click.echo(
            f"exported {summary.pages} page(s) and {summary.files} file(s) ({summary.bytes / 2**20:.1f} MiB) "
            f"to {summary.out}; open {(summary.out / 'index.html').resolve().as_uri()}"
        )
        return
    from scratchworld_dist.viewer import serve

    def ready(url: str) -> None:
        click.echo(f"scratchworld viewer on {url} (Ctrl-C to stop)")

    asyncio.run(serve(site, port, ready))
