"""The class every benchmark kind is built on: the facets each layer of the driver defines, joined.

A kind (the built-in ``tasks``, ``drag``, ``perception`` and ``audit``, or a plugin's) subclasses ``Kind``, sets
its traits (``name``, ``title``, ``tables``, ``config_section``...) and overrides what it does otherwise than the
defaults: planning (``KindPlanning``, in ``sweep``), its rows (``KindRows``, in ``results``), its report
(``KindReport``, in ``reports``), its part of the viewer (``KindPanel``, in ``viewer``) and its commands
(``KindCommands``, in ``cli``). Its instance is
registered as an entry point of ``scratchworld.kinds`` (see docs/architecture.md, "Add a kind").
"""

from scratchworld_dist.cli._kind import KindCommands
from scratchworld_dist.reports import KindReport
from scratchworld_dist.results import KindRows
from scratchworld_dist.sweep import KindPlanning
from scratchworld_dist.viewer import KindPanel


class Kind(KindPlanning, KindRows, KindReport, KindPanel, KindCommands):
    """One benchmark, as the driver plans, records, reports and shows it, and its commands."""


__all__ = ["Kind"]
