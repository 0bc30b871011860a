"""``--render``, the one evaluation condition every evaluating command takes the same way."""

from __future__ import annotations

import click

render_option = click.option(
    "--render",
    type=click.Choice(["on_demand", "every_frame"]),
    help="When evaluations draw the stage: only when a script reads the picture (default), or every frame.",
)
