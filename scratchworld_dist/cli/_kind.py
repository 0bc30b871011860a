"""What the command line asks of a benchmark kind: the commands of its own (``scratchworld drag make``, ``validate``
for task suites...), added to the ``scratchworld`` group beside the commands every kind shares."""

from __future__ import annotations

import click

from scratchworld_dist.kinds import KindTraits


class KindCommands(KindTraits):
    """The command-line facet of a kind. Default: no command of its own (``run``, ``plan``, ``report``... serve
    every kind)."""

    def commands(self) -> list[click.Command]:
        """Its commands (a group of them, ``drag``, or top-level ones); imported only when the CLI starts."""
        return []
