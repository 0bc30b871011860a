"""A listener on 127.0.0.1 that counts whoever reaches it: TCP connections and UDP datagrams on one port.

Stands for the services a cluster node keeps on loopback (Ray's GCS and dashboard, a local model
server); tests assert that nothing a page does ever arrives here.
"""

from __future__ import annotations

import contextlib
import socket
import threading
from types import TracebackType


class LoopbackListener:
    """Accepts and records TCP connections (their first bytes) and UDP datagrams until closed."""

    def __init__(self) -> None:
        self._tcp = socket.create_server(("127.0.0.1", 0))
        self.port: int = self._tcp.getsockname()[1]
        self._udp = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self._udp.bind(("127.0.0.1", self.port))
        for sock in (self._tcp, self._udp):
            sock.settimeout(0.1)  # so the threads notice ``close``
        self._closed = threading.Event()
        self._lock = threading.Lock()
        self._connections: list[bytes] = []
        self._datagrams: list[bytes] = []
        self._threads = [
            threading.Thread(target=self._accept, name="loopback-tcp", daemon=True),
            threading.Thread(target=self._receive, name="loopback-udp", daemon=True),
        ]
        for thread in self._threads:
            thread.start()

    @property
    def connections(self) -> list[bytes]:
        with self._lock:
            return list(self._connections)

    @property
    def datagrams(self) -> list[bytes]:
        with self._lock:
            return list(self._datagrams)

    def _accept(self) -> None:
        while not self._closed.is_set():
            try:
                connection, _ = self._tcp.accept()
            except OSError:  # the poll timeout, or closed
                continue
            with connection:
                connection.settimeout(2)
                first = b""
                with contextlib.suppress(OSError):
                    first = connection.recv(200)
                with self._lock:
                    self._connections.append(first)
                with contextlib.suppress(OSError):
                    connection.sendall(b"HTTP/1.0 200 OK\r\nAccess-Control-Allow-Origin: *\r\n\r\nreached")

    def _receive(self) -> None:
        while not self._closed.is_set():
            try:
                data, _ = self._udp.recvfrom(4096)
            except OSError:
                continue
            with self._lock:
                self._datagrams.append(data[:200])

    def close(self) -> None:
        self._closed.set()
        for thread in self._threads:
            thread.join()
        self._tcp.close()
        self._udp.close()

    def __enter__(self) -> LoopbackListener:
        return self

    def __exit__(
        self, exc_type: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None
    ) -> None:
        self.close()
