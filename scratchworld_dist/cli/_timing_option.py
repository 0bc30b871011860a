"""``--timing``: how virtual frames are timed, taken the same way by every evaluating command."""

from __future__ import annotations

import click

timing_option = click.option(
    "--timing",
    type=click.Choice(["ideal", "calibrated"]),
    help="Virtual-clock frame timing: exactly on time, or late by the calibrated per-frame model "
    "(default: calibrated for upstream in virtual time, ideal otherwise).",
)
