"""``scratchworld gui``: serve the editor for a person to look at."""

from __future__ import annotations

import threading

import click


@click.command("gui")
@click.option("--port", type=int, default=8601, show_default=True, help="Port on 127.0.0.1 (0: any free port).")
def gui_command(port: int) -> None:
    """Serve the Scratch editor on 127.0.0.1 until Ctrl-C."""
    from workers.editor import EditorServer

    with EditorServer(port=port) as server:
        click.echo(f"Scratch editor (with the scratchworld bridge) at {server.url}")
        click.echo("Press Ctrl-C to stop.")
        threading.Event().wait()
