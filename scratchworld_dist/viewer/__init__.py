"""``scratchworld view``: a run's report, jobs and trajectories in a browser, served locally or exported."""

from scratchworld_dist.viewer._export import ExportSummary, export_site
from scratchworld_dist.viewer._site import Resource, ViewerSite

__all__ = ["ExportSummary", "Resource", "ViewerSite", "export_site"]
