"""The editor on this machine: ``scratchworld gui`` serves it for a person to look at; ``scratchworld capacity``
measures how many editors this machine holds for agents that wait on a model.

A local run derives this by itself; a cluster node declares it when it joins
(``ray start --resources='{"browser": N}'``), so this prints N, measured on the node.
"""

from __future__ import annotations

import os
import threading

import click


@click.command("capacity", epilog="Example: scratchworld capacity --clock virtual --mode primitive --margin 0.25")
@click.option("--clock", type=click.Choice(["virtual", "real"]), default="virtual", help="The episodes' clock.")
@click.option("--mode", type=click.Choice(["composite", "primitive"]), default="composite", help="The episodes' mode.")
@click.option(
    "--margin",
    type=click.FloatRange(0, 1, max_open=True),
    default=None,
    help="Share of CPU and spare memory kept free (0.25).",
)
@click.option(
    "--reserve-mb", type=click.IntRange(min=0), default=None, help="Memory kept for the rest of the node (1024)."
)
def capacity_command(clock: str, mode: str, margin: float | None, reserve_mb: int | None) -> None:
    """Measure a waiting editor's CPU and memory here and print the browser slots they allow."""
    from scratchworld_dist.scheduling import derive_local  # imports Ray and the browser stack: only for this command
    from scratchworld_dist.sweep import Limits
    from workers.node import harness_fingerprint

    overrides = {"capacity_margin": margin, "memory_reserve_mb": reserve_mb}
    limits = Limits.model_validate({key: value for key, value in overrides.items() if value is not None})
    derivation = derive_local(limits, clock, harness_fingerprint().digest, os.cpu_count() or 1, mode)  # type: ignore[arg-type]
    click.echo(derivation.describe())
    click.echo(f"""ray start --address HEAD:6379 --resources='{{"browser": {derivation.slots}}}'""")


@click.command("gui", epilog="Example: scratchworld gui --port 8601")
@click.option("--port", type=int, default=8601, show_default=True, help="Port on 127.0.0.1 (0: any free port).")
def gui_command(port: int) -> None:
    """Serve the Scratch editor on 127.0.0.1 until Ctrl-C."""
    from workers.editor import EditorServer

    with EditorServer(port=port) as server:
        click.echo(f"Scratch editor (with the scratchworld bridge) at {server.url}")
        click.echo("Press Ctrl-C to stop.")
        threading.Event().wait()
