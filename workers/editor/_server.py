"""A static file server for the editor, bound to 127.0.0.1 only, and the page's only way out.

The bundle's webpack ``publicPath`` is ``/``, so its ``chunks/``, ``static/`` and ``libraries/``
must sit at the web root next to our ``index.html`` and ``bridge.js``. A threaded stdlib server
in the worker process does that with no extra dependency; Playwright routing was the
alternative, but it pipes every response body through Python (see benchmarks/editor_startup.py).

The same server is the browser's HTTP proxy for every destination, loopback included
(``BrowserSession`` launches Chromium so), and it answers only requests for its own origin:
whatever the page is made to fetch elsewhere (by a task's script, a project, or an agent's
clicks: images, workers, WebSockets, extension services) is refused here and noted, so nothing
on the node's loopback or network (Ray, model servers, dashboards) is reachable from a page.

With editor origins (``EditorOrigins``: editors sharing one browser context, each at a
``127.0.0.2:<port>`` origin of its own), the server also answers the live editor origins, and only
for that origin's own page (``Sec-Fetch-Site`` ``none``: the browser's navigation, or ``same-origin``),
so no editor can frame, open or fetch a sibling's origin and reach its storage. Every script the pages
load (the editor bundle, the bare page's packages, and our page modules) then comes from the *shared
origin* (``SHARED_ORIGIN``, a fixed address this server answers as the proxy), which serves nothing else
and only as scripts: one URL for every editor, in every browser, so the HTTP cache and V8's code cache
serve them from the second opening on, without a request to this server, and a node's browsers can start
from one cache (``_cache_template``). Every script's URL carries its content's digest, and the shared
origin answers a script only at its current digest, so no cache ever holds other content under a URL a
page loads.
"""

from __future__ import annotations

import functools
import io
import logging
import os
import re
import sys
import threading
from collections import OrderedDict
from functools import cached_property
from http.server import SimpleHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from types import TracebackType
from typing import BinaryIO
from urllib.parse import SplitResult, parse_qs, unquote, urlsplit

from workers.contract import EditorBundleMissingError, EvaluationPage
from workers.editor._origins import SHARED_ORIGIN, EditorOrigins
from workers.node import (
    BARE_BUILT_FILES,
    BARE_DIR,
    BARE_PAGE,
    BARE_VENDOR_PACKAGES,
    BARE_VENDOR_URL,
    BUNDLE_FILE,
    BUNDLE_PACKAGE,
    EDITOR_PAGE,
    OWN_FILES,
    PAGES,
    default_gui_dir,
    file_digest,
)

log = logging.getLogger(__name__)

_SCRIPT = re.compile(r'<script src="([^"]+)"></script>')

OWN_PAGE_FETCHES = frozenset({"none", "same-origin"})
"""``Sec-Fetch-Site`` values answered at an editor origin: the browser's own navigation and the page's own
requests. A sibling editor's frame, window or fetch is ``same-site`` (Chromium sets the header; pages cannot)."""

REFUSALS_KEPT = 200
"""Distinct refused requests remembered per server (the least recent are forgotten)."""


class EditorAssets:
    """Where the pages' files are on disk; checked once so a missing install fails early.

    The editor bundle must be installed. The bare evaluation page's packages may be missing (a
    checkout copied without them): ``bare_missing`` then says why, and opening a bare page fails with it.
    """

    def __init__(self, gui_dir: Path | None = None) -> None:
        self.gui_dir = (gui_dir or default_gui_dir()).resolve()
        # Resolved like the files it serves: node_modules may be a link (shared install, worktree, pnpm).
        self.dist_dir = (self.gui_dir / "node_modules" / BUNDLE_PACKAGE / "dist").resolve()
        for name in OWN_FILES:
            if not (self.gui_dir / name).is_file():
                raise EditorBundleMissingError(f"{self.gui_dir / name} is missing (it ships with the repository)")
        if not (self.dist_dir / BUNDLE_FILE).is_file():
            raise EditorBundleMissingError(
                f"the Scratch editor bundle is not installed: {self.dist_dir / BUNDLE_FILE} is missing; "
                "run ./install.sh (the README's install command)"
            )
        packages = self.gui_dir / BARE_DIR / "node_modules" / "@scratch"
        self.build_dir = (self.gui_dir / BARE_DIR / "build").resolve()  # may be a link, like node_modules
        self.vendor_dirs = {name: (packages / name / "dist" / "web").resolve() for name in BARE_VENDOR_PACKAGES}
        missing = [str(self.gui_dir / name) for name in BARE_BUILT_FILES if not (self.gui_dir / name).is_file()]
        missing += [str(path) for path in self.vendor_dirs.values() if not path.is_dir()]
        self.bare_missing = (
            f"the bare evaluation page is not installed ({', '.join(missing)} missing); run ./install.sh"
            if missing
            else None
        )

    @cached_property
    def script_versions(self) -> dict[str, str]:
        """Every script the pages load (our modules, the bundle, the bare page's packages), each with a digest
        of its content: the query that keeps a cached copy of other content from being used."""
        versions: dict[str, str] = {}
        for page in PAGES:
            for name in _SCRIPT.findall((self.gui_dir / page).read_text(encoding="utf-8")):
                path = self.resolve(name)
                if path is not None:
                    versions[name] = _version_of(path)
        return versions

    @cached_property
    def bundle_version(self) -> str:
        """The editor bundle's content digest, whichever scripts the pages load (the node's cache template is
        kept per bundle)."""
        return _version_of((self.dist_dir / BUNDLE_FILE).resolve())

    def page_path(self, page: EvaluationPage) -> str:
        """The URL path of the editor page or the bare evaluation page."""
        return f"/{BARE_PAGE if page == 'bare' else EDITOR_PAGE}"

    def resolve(self, url_path: str) -> Path | None:
        """Map a request path to a file, refusing anything outside the roots."""
        relative = unquote(urlsplit(url_path).path).lstrip("/") or EDITOR_PAGE
        root = self.gui_dir if relative in OWN_FILES else self.dist_dir
        if relative in BARE_BUILT_FILES:
            root, relative = self.build_dir, relative.rsplit("/", 1)[-1]
        elif relative.startswith(BARE_VENDOR_URL):
            package, _, relative = relative.removeprefix(BARE_VENDOR_URL).partition("/")
            if package not in self.vendor_dirs:
                return None
            root = self.vendor_dirs[package]
        candidate = (root / relative).resolve()
        if not candidate.is_relative_to(root) or not candidate.is_file():
            return None
        return candidate


def _version_of(path: Path) -> str:
    """A file's content digest, computed again only when its size or modification time changed."""
    stat = path.stat()
    return _content_version(path, stat.st_size, stat.st_mtime_ns)


@functools.lru_cache(maxsize=64)
def _content_version(path: Path, size: int, mtime_ns: int) -> str:
    """``file_digest`` once per file state: each browser session serves the 17 MB bundle at its digest."""
    return file_digest(path)


def with_shared_scripts(html: str, shared_origin: str, versions: dict[str, str]) -> str:
    """A page whose scripts load from ``shared_origin``, each at its content's ``versions``, as CORS scripts
    so that their errors keep their messages."""

    def shared(match: re.Match[str]) -> str:
        name = match.group(1)
        query = f"?v={versions[name]}" if name in versions else ""
        return f'<script src="{shared_origin}/{name}{query}" crossorigin="anonymous"></script>'

    return _SCRIPT.sub(shared, html)


class _Handler(SimpleHTTPRequestHandler):
    assets: EditorAssets
    refusals: Refusals
    origins: EditorOrigins | None
    """With editor origins, the shared origin serves installed scripts only (see the module docstring)."""

    _at_editor_origin = False
    _shared_script = False
    _refused = False

    def parse_request(self) -> bool:
        """Go on only with a request for an origin we answer, whether sent directly or as a proxy request."""
        self._at_editor_origin = self._shared_script = self._refused = (
            False  # per request (a connection may carry several)
        )
        if not super().parse_request():
            return False
        target = urlsplit(self.path)
        if target.scheme:  # absolute form: the browser uses us as its proxy
            netloc = target.netloc if target.scheme == "http" else None
        else:  # origin form (a CONNECT's authority parses as a path here, and is refused below)
            netloc = self.headers.get("Host") if self.command != "CONNECT" and self.path.startswith("/") else None
        own = netloc is not None and self._answers(netloc, target)
        if not own:
            self.refusals.note(f"{self.command} {self.path}")
            self._refused = True
            self.close_connection = True
            self.send_error(403, "the editor page may load the editor's own files only")
        return own

    def _answers(self, netloc: str, target: SplitResult) -> bool:
        port = self.server.server_address[1]
        if netloc in (f"127.0.0.1:{port}", f"localhost:{port}"):
            return self.origins is None  # with editor origins, the pages are there and the scripts shared
        if self.origins is not None and f"http://{netloc}" == SHARED_ORIGIN:
            script = self.headers.get("Sec-Fetch-Dest") == "script"
            name = unquote(target.path).lstrip("/")
            current = self.assets.script_versions.get(name)
            self._shared_script = script and current is not None and parse_qs(target.query).get("v") == [current]
            return self._shared_script
        if self.origins is not None and self.origins.is_live(netloc):
            self._at_editor_origin = self.headers.get("Sec-Fetch-Site") in OWN_PAGE_FETCHES
            return self._at_editor_origin
        return False

    def send_head(self) -> BinaryIO | None:  # type: ignore[override]
        path = self.assets.resolve(self.path)
        if path is None:
            self.send_error(404)
            return None
        if self._at_editor_origin and path.name in PAGES and path.parent == self.assets.gui_dir:
            page = path.read_text(encoding="utf-8")
            body = with_shared_scripts(page, SHARED_ORIGIN, self.assets.script_versions).encode()
            self.send_response(200)
            self.send_header("Content-Type", "text/html; charset=utf-8")
            self.send_header("Content-Length", str(len(body)))
            self.end_headers()
            return io.BytesIO(body)
        return super().send_head()

    def translate_path(self, path: str) -> str:
        return str(self.assets.resolve(path))

    def list_directory(self, path: str | os.PathLike[str]) -> None:
        self.send_error(404)

    def end_headers(self) -> None:
        # Nothing from an editor origin is kept: a page could otherwise load a sibling's page from the HTTP
        # cache (all 127.0.0.2 ports are one site, one cache partition) without asking us, as a frame at the
        # sibling's origin. An editor's own files are loaded once in its life, so nothing is lost. Nor is a
        # refusal kept: a page refused a later editor's page would otherwise leave it refused in the cache.
        keep = not (self._at_editor_origin or self._refused)
        self.send_header("Cache-Control", "max-age=86400" if keep else "no-store")
        if self._shared_script:
            self.send_header("Access-Control-Allow-Origin", "*")
        super().end_headers()

    def log_message(self, format: str, *args: object) -> None:
        """Requests are not worth a log line each."""


class Refusals:
    """Requests the server refused (a page, or Chromium itself, tried to reach something else): a count,
    and the latest distinct ones, so the browser's own repeated background calls (autofill, sign-in,
    component updates, all refused) cannot push a page's attempts out of view. Requests are told apart
    without their query: Chromium's update checks carry a fresh key each time, and 200 of them would
    otherwise be 200 distinct requests."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._latest: OrderedDict[str, None] = OrderedDict()
        self.count = 0

    def note(self, request: str) -> None:
        request = request.split("?", 1)[0][:300]
        with self._lock:
            self.count += 1
            first = request not in self._latest
            self._latest[request] = None
            self._latest.move_to_end(request)
            while len(self._latest) > REFUSALS_KEPT:
                self._latest.popitem(last=False)
        if first:
            log.info("refused a request from the editor page: %s", request)

    @property
    def latest(self) -> list[str]:
        with self._lock:
            return list(self._latest)


class _Server(ThreadingHTTPServer):
    daemon_threads = True

    def handle_error(self, request: object, client_address: object) -> None:
        """A browser that closes mid-download (a page closed, Chromium killed) is routine, not an error."""
        if not isinstance(sys.exc_info()[1], ConnectionError):
            super().handle_error(request, client_address)  # type: ignore[arg-type]


class EditorServer:
    """Serves the editor on an ephemeral 127.0.0.1 port from a daemon thread (and, given ``origins``, at the
    live editor origins, with the installed scripts from that port: the shared origin)."""

    def __init__(self, assets: EditorAssets | None = None, port: int = 0, origins: EditorOrigins | None = None) -> None:
        self.assets = assets or EditorAssets()
        self.origins = origins
        self._port = port
        self._httpd: ThreadingHTTPServer | None = None
        self._thread: threading.Thread | None = None
        self.refusals = Refusals()
        """What pages served by this server tried to reach besides it."""

    @cached_property
    def _handler(self) -> type[_Handler]:
        return type(
            "EditorRequestHandler",
            (_Handler,),
            {"assets": self.assets, "refusals": self.refusals, "origins": self.origins},
        )

    @property
    def url(self) -> str:
        """The editor page's address."""
        return self.page_url("editor")

    def page_url(self, page: EvaluationPage, origin: str | None = None) -> str:
        """The address of the editor page (``editor``) or the bare evaluation page (``bare``), at the shared
        origin or at an editor ``origin``."""
        if self._httpd is None:
            raise RuntimeError("the editor server is not running")
        host, port = self._httpd.server_address[:2]
        return f"{origin or f'http://{host}:{port}'}{self.assets.page_path(page)}"

    @property
    def proxy(self) -> str:
        """This server as a browser's proxy (``--proxy-server``)."""
        if self._httpd is None:
            raise RuntimeError("the editor server is not running")
        return f"http://127.0.0.1:{self._httpd.server_address[1]}"

    def start(self) -> EditorServer:
        if self._httpd is not None:
            raise RuntimeError("the editor server is already running")
        self._httpd = _Server(("127.0.0.1", self._port), self._handler)
        self._thread = threading.Thread(target=self._httpd.serve_forever, name="editor-server", daemon=True)
        self._thread.start()
        return self

    def stop(self) -> None:
        if self._httpd is None:
            return
        self._httpd.shutdown()
        self._httpd.server_close()
        if self._thread is not None:
            self._thread.join()
        self._httpd = None
        self._thread = None

    def __enter__(self) -> EditorServer:
        return self.start()

    def __exit__(
        self, exc_type: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None
    ) -> None:
        self.stop()
