"""A loopback port that refuses connections for as long as a test holds it.

A port found free and then released can be handed to the next server that binds port 0 (another test's
model server, say), so a test that expects a refusal would reach that server instead. Holding the port
bound but not listening makes the refusal certain: the kernel answers a connection with a reset and
gives the port to no one else until the test lets go.
"""

from __future__ import annotations

import socket
from collections.abc import Iterator
from contextlib import contextmanager


@contextmanager
def closed_port() -> Iterator[int]:
    """Yield a 127.0.0.1 port that is bound by no listener: every connection to it is refused."""
    with socket.socket() as held:
        held.bind(("127.0.0.1", 0))
        yield int(held.getsockname()[1])
