"""The viewer's templates (Jinja2, autoescaped) and the files every page links to.

Pages link to each other and to ``static/`` by relative paths only, so the same HTML works from
the local server, from any static server and from ``file://``.
"""

from __future__ import annotations

from importlib import resources
from typing import Any

import jinja2

STATIC_FILES = ("viewer.css", "jobs.js", "video.js")
"""Everything a page loads besides its own data: shipped in the package, never fetched from a CDN."""

_ENVIRONMENT = jinja2.Environment(
    loader=jinja2.PackageLoader("scratchworld_dist.viewer", "templates"),
    autoescape=True,
    undefined=jinja2.StrictUndefined,
    trim_blocks=True,
    lstrip_blocks=True,
)


def render_page(template: str, root: str, **context: Any) -> bytes:
    """The page ``template`` with ``root`` the relative path from the page back to the site's root."""
    return _ENVIRONMENT.get_template(template).render(root=root, **context).encode("utf-8")


def static_file(name: str) -> bytes | None:
    """A file of ``static/`` by name (None for any other name)."""
    if name not in STATIC_FILES:
        return None
    return resources.files("scratchworld_dist.viewer").joinpath("static", name).read_bytes()
