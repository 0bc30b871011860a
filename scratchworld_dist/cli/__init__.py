"""The ``scratchworld`` command line: a thin client of the library."""

from scratchworld_dist.cli._main import main

__all__ = ["main"]
