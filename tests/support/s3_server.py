"""A real S3 API server on 127.0.0.1 for the object-storage tests: moto's server (from PyPI) in a subprocess,
reached through a TCP relay the test can cut (``down``) and restore (``up``) without losing the bucket's
contents, as when a store goes away mid-run and comes back.

Clients find it through the standard environment (``S3Server.env``: ``AWS_ENDPOINT_URL`` and test credentials),
which s3fs/botocore read; nothing in the product is told it is a test.
"""

from __future__ import annotations

import contextlib
import os
import socket
import subprocess
import sys
import threading
import time
import uuid
from collections.abc import Iterator
from pathlib import Path
from typing import Any

MOTO_SERVER = str(Path(sys.executable).with_name("moto_server"))

CREDENTIALS = {
    "AWS_ACCESS_KEY_ID": "testing",
    "AWS_SECRET_ACCESS_KEY": "testing-secret-never-logged",
    "AWS_DEFAULT_REGION": "us-east-1",
    "AWS_EC2_METADATA_DISABLED": "true",
}


def _free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


def _wait_listening(port: int, process: subprocess.Popen[bytes], limit_s: float = 60) -> None:
    """Until something accepts on ``port`` (the server is up), or the process died."""
    deadline = time.monotonic() + limit_s
    while time.monotonic() < deadline:
        if process.poll() is not None:
            raise RuntimeError(f"moto_server exited with {process.returncode}")
        with contextlib.suppress(OSError), socket.create_connection(("127.0.0.1", port), timeout=0.5):
            return
        threading.Event().wait(0.05)
    raise RuntimeError(f"moto_server did not listen on {port} within {limit_s} s")


class Relay:
    """Forwards TCP connections from its own port to ``target``; ``down`` closes the port and every connection
    (clients get refused), ``up`` listens on the same port again."""

    def __init__(self, target: int) -> None:
        self.target = target
        self.port = _free_port()
        self._lock = threading.Lock()
        self._sockets: set[socket.socket] = set()
        self._listener: socket.socket | None = None
        self.up()

    def up(self) -> None:
        listener = socket.create_server(("127.0.0.1", self.port), reuse_port=False)
        self._listener = listener
        threading.Thread(target=self._accept, args=(listener,), daemon=True).start()

    def down(self) -> None:
        with self._lock:
            listener, self._listener = self._listener, None
            sockets, self._sockets = self._sockets, set()
        if listener is not None:
            with contextlib.suppress(OSError):
                listener.shutdown(socket.SHUT_RDWR)
            listener.close()
        for sock in sockets:
            with contextlib.suppress(OSError):
                sock.shutdown(socket.SHUT_RDWR)
            sock.close()

    def _accept(self, listener: socket.socket) -> None:
        while True:
            try:
                client, _ = listener.accept()
            except OSError:
                return
            try:
                server = socket.create_connection(("127.0.0.1", self.target))
            except OSError:
                client.close()
                continue
            with self._lock:
                if self._listener is not listener:
                    client.close()
                    server.close()
                    return
                self._sockets |= {client, server}
            for a, b in ((client, server), (server, client)):
                threading.Thread(target=self._pipe, args=(a, b), daemon=True).start()

    def _pipe(self, source: socket.socket, sink: socket.socket) -> None:
        try:
            while data := source.recv(65536):
                sink.sendall(data)
        except OSError:
            pass
        finally:
            for sock in (source, sink):
                with contextlib.suppress(OSError):
                    sock.shutdown(socket.SHUT_RDWR)


class S3Server:
    """moto's S3 server on 127.0.0.1 behind a ``Relay``; ``bucket()`` makes a fresh bucket."""

    def __init__(self, log: Path) -> None:
        self.moto_port = _free_port()
        with log.open("wb") as out:
            self.process = subprocess.Popen(
                [MOTO_SERVER, "-H", "127.0.0.1", "-p", str(self.moto_port)],
                stdout=out,
                stderr=subprocess.STDOUT,
                start_new_session=True,
            )
        _wait_listening(self.moto_port, self.process)
        self.relay = Relay(self.moto_port)
        self.endpoint = f"http://127.0.0.1:{self.relay.port}"
        self.env = {**CREDENTIALS, "AWS_ENDPOINT_URL": self.endpoint}

    def client(self) -> Any:
        """A boto3 client straight to moto (unaffected by the relay), for the test's own looks at the bucket."""
        import boto3

        return boto3.client(
            "s3",
            endpoint_url=f"http://127.0.0.1:{self.moto_port}",
            aws_access_key_id=CREDENTIALS["AWS_ACCESS_KEY_ID"],
            aws_secret_access_key=CREDENTIALS["AWS_SECRET_ACCESS_KEY"],
            region_name=CREDENTIALS["AWS_DEFAULT_REGION"],
        )

    def bucket(self) -> str:
        name = f"runs-{uuid.uuid4().hex[:12]}"
        self.client().create_bucket(Bucket=name)
        return name

    def keys(self, bucket: str, prefix: str = "") -> list[str]:
        pages = self.client().get_paginator("list_objects_v2").paginate(Bucket=bucket, Prefix=prefix)
        return sorted(obj["Key"] for page in pages for obj in page.get("Contents", []))

    def read(self, bucket: str, key: str) -> bytes:
        return self.client().get_object(Bucket=bucket, Key=key)["Body"].read()

    def close(self) -> None:
        self.relay.down()
        with contextlib.suppress(ProcessLookupError):
            os.killpg(self.process.pid, 9)
        self.process.wait()


@contextlib.contextmanager
def s3_environment(server: S3Server) -> Iterator[None]:
    """``server``'s endpoint and credentials in this process's environment (restored after)."""
    saved = {key: os.environ.get(key) for key in server.env}
    os.environ.update(server.env)
    try:
        yield
    finally:
        for key, value in saved.items():
            if value is None:
                os.environ.pop(key, None)
            else:
                os.environ[key] = value


def s3_server_fixture(tmp_path_factory: object) -> Iterator[S3Server]:
    """The body of a module's ``s3`` fixture: the server, its endpoint and credentials in the environment, views
    and mirrors under a temporary cache folder (``XDG_CACHE_HOME``) while the module runs."""
    import pytest

    folder = tmp_path_factory.mktemp("s3")  # type: ignore[attr-defined]
    server = S3Server(folder / "moto.log")
    try:
        with s3_environment(server), pytest.MonkeyPatch.context() as patch:
            patch.setenv("XDG_CACHE_HOME", str(folder / "cache"))
            yield server
    finally:
        server.close()
