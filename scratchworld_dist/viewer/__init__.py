"""``scratchworld view``: a run's report, jobs and trajectories in a browser, served locally or exported; what it
asks of a benchmark kind (``KindPanel``: a run page's body and plots, a job's panel, comparison pages).

The server (``serve``, aiohttp) is imported on first use: reading the site needs no web server."""

import typing

import workers
from scratchworld_dist.viewer._export import ExportSummary, export_site
from scratchworld_dist.viewer._kind import AttemptPanel, KindPanel, RunComparison
from scratchworld_dist.viewer._site import Resource, ViewerSite

if typing.TYPE_CHECKING:
    from scratchworld_dist.viewer._server import serve

__getattr__ = workers.lazy_exports(__name__, {"._server": ("serve",)})

__all__ = [
    "AttemptPanel",
    "ExportSummary",
    "KindPanel",
    "Resource",
    "RunComparison",
    "ViewerSite",
    "export_site",
    "serve",
]
