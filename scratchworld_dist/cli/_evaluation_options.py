"""``--render`` and ``--evaluation-page``: evaluation conditions every evaluating command takes the same way."""

from __future__ import annotations

import click

render_option = click.option(
    "--render",
    type=click.Choice(["on_demand", "every_frame"]),
    help="When evaluations draw the stage: only when a script reads the picture (default), or every frame.",
)

page_option = click.option(
    "--evaluation-page",
    "page",
    type=click.Choice(["bare", "editor"]),
    help="The page evaluations run in: the VM without the editor GUI (default; a script that needs the "
    "editor runs there anyway), or the whole Scratch editor, the reference.",
)
