"""The origins editor pages get when they share one browser context: one per opening, never reused uncleared.

Storage (cookies with port-bound cookies on, localStorage, IndexedDB, cache storage, service workers,
BroadcastChannel) is kept per origin, so an origin of its own is what keeps an editor apart from its
siblings in the shared context. The origins are ``http://127.0.0.2:<port>``: nothing listens there, the
editor server answers them as Chromium's proxy, and every other 127.0.0.1 port stays refused. All ports
of one host are one *site*, so the editor bundle that all of them load from the shared origin keeps one
HTTP-cache entry and one V8 code-cache entry.

The shared origin is a fixed address too (``SHARED_ORIGIN``), the same in every browser on every node, so
that a cache entry made in one browser is found in another (see ``_cache_template``).
"""

from __future__ import annotations

import threading

EDITOR_HOST = "127.0.0.2"

FIRST_PORT = 10081
"""Above every port Chromium refuses to load from (its "unsafe ports" end at 10080)."""
LAST_PORT = 65535

SHARED_ORIGIN = f"http://127.0.0.3:{FIRST_PORT}"
"""Where every page loads its scripts: nothing listens there either; the editor server answers it as the
proxy, with installed scripts only, each at its content's version."""


class OriginsExhaustedError(RuntimeError):
    """Every port is taken by a live editor or was retired uncleared."""


class EditorOrigins:
    """Hands out editor origins in port order, wrapping only past ports that were released cleared.

    An origin is live from ``take`` until ``release``; a page's request is answered only at a live origin.
    Released with ``cleared=False`` (its storage could not be cleared), a port is never handed out again.
    Thread-safe: the server's request threads read it while the session takes and releases.
    """

    def __init__(self, first: int = FIRST_PORT, last: int = LAST_PORT) -> None:
        self._first, self._last = first, last
        self._next = first
        self._live: set[int] = set()
        self._retired: set[int] = set()
        self._lock = threading.Lock()

    def take(self) -> str:
        """A fresh origin, live until released."""
        with self._lock:
            for _ in range(self._last - self._first + 1):
                port, self._next = self._next, self._next + 1 if self._next < self._last else self._first
                if port not in self._live and port not in self._retired:
                    self._live.add(port)
                    return f"http://{EDITOR_HOST}:{port}"
        raise OriginsExhaustedError(f"no editor origin left on {EDITOR_HOST}:{self._first}-{self._last}")

    def release(self, origin: str, *, cleared: bool) -> None:
        """The origin's editor closed; its port may come round again only if its storage was cleared."""
        port = int(origin.rsplit(":", 1)[1])
        with self._lock:
            self._live.discard(port)
            if not cleared:
                self._retired.add(port)

    def is_live(self, netloc: str) -> bool:
        """Whether ``host:port`` is an editor origin in use."""
        host, _, port = netloc.rpartition(":")
        with self._lock:
            return host == EDITOR_HOST and port.isdigit() and int(port) in self._live
