"""The class every benchmark kind is built on: the facets each layer of the driver defines, joined.

A kind (the built-in ``tasks``, ``drag``, ``perception`` and ``audit``, or a plugin's) subclasses ``Kind``, sets
its traits (``name``, ``title``, ``tables``, ``config_section``...) and overrides what it does otherwise than the
defaults: planning (``KindPlanning``, in ``sweep``), its rows (``KindRows``, in ``results``), its report
(``KindReport``, in ``reports``) and its part of the viewer (``KindPanel``, in ``viewer``). Its instance is
registered as an entry point of ``scratchworld.kinds``, and its commands, if it has any, as entry points of
``scratchworld.commands`` (see docs/architecture.md, "Add a kind"), so the command line lists them without
loading any kind.
"""

from scratchworld_dist.reports import KindReport
from scratchworld_dist.results import KindRows
from scratchworld_dist.sweep import KindPlanning
from scratchworld_dist.viewer import KindPanel


class Kind(KindPlanning, KindRows, KindReport, KindPanel):
    """One benchmark, as the driver plans, records, reports and shows it."""


__all__ = ["Kind"]
