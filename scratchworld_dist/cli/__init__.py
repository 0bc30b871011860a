"""The ``scratchworld`` command line: a thin client of the library.

``main`` is imported on first use: its command table holds every installed kind's commands, so building it loads
the kinds, and a kind imports ``cli._kind`` (its commands facet) as it loads. Importing a kind first (``from
scratchworld_dist.kinds.tasks.report import ...``) then never builds the table halfway through its own import."""

import typing

import workers

if typing.TYPE_CHECKING:
    from scratchworld_dist.cli._main import main

__getattr__ = workers.lazy_exports(__name__, {"._main": ("main",)})

__all__ = ["main"]
