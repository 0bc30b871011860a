"""The viewer answers only requests addressed to a loopback name: a page on another site that rebinds its DNS
name to 127.0.0.1 (DNS rebinding) sends its own name as ``Host`` and must not read a run. Real HTTP requests
to a served viewer, each with the exact ``Host`` header it names."""

from __future__ import annotations

import asyncio
import http.client
from collections.abc import AsyncIterator
from pathlib import Path
from urllib.parse import urlsplit

import pytest

from scratchworld_dist.viewer import ViewerSite
from scratchworld_dist.viewer._server import serve
from tests.support.run_dirs import job, make_run


@pytest.fixture
async def port(tmp_path: Path) -> AsyncIterator[int]:
    """A served viewer of a small run; its port."""
    run = make_run(tmp_path / "run", [job("job-passed", task_id="t1")], planned=1, tasks=1)
    announced: asyncio.Future[str] = asyncio.get_running_loop().create_future()
    task = asyncio.create_task(serve(ViewerSite([run]), 0, announced.set_result))
    try:
        url = await asyncio.wait_for(announced, 30)
        bound = urlsplit(url).port
        assert bound is not None
        yield bound
    finally:
        task.cancel()
        await asyncio.gather(task, return_exceptions=True)


def get(port: int, host: str | None, path: str = "/runs/0/jobs-data.js") -> tuple[int, bytes]:
    """GET ``path`` from 127.0.0.1:``port`` with ``Host: host`` (None: no Host header at all)."""
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=30)
    try:
        connection.putrequest("GET", path, skip_host=True)
        if host is not None:
            connection.putheader("Host", host)
        connection.endheaders()
        response = connection.getresponse()
        return response.status, response.read()
    finally:
        connection.close()


@pytest.mark.parametrize(
    "host", ["127.0.0.1:{port}", "localhost:{port}", "LOCALHOST", "[::1]:{port}", "127.0.0.1", "localhost:9000"]
)
async def test_a_loopback_host_reads_the_run(port: int, host: str) -> None:
    status, body = await asyncio.to_thread(get, port, host.format(port=port))
    assert status == 200
    assert b"job-passed" in body


@pytest.mark.parametrize(
    "host",
    [
        "attacker.example:{port}",  # a rebound DNS name: the browser sends the page's own host
        "attacker.example",
        "127.0.0.1.attacker.example:{port}",
        "localhost.attacker.example",
        "127.0.0.2:{port}",
        "0.0.0.0:{port}",
        "[::1]x",
        "127.0.0.1:{port}@attacker.example",
        "",
    ],
)
async def test_any_other_host_is_refused_with_421_and_no_run_data(port: int, host: str) -> None:
    status, body = await asyncio.to_thread(get, port, host.format(port=port))
    assert status == 421
    assert body == b"this viewer answers only to 127.0.0.1, localhost and [::1]\n"
    for path in ("/", "/index.html", "/runs/0/index.html", "/runs/0/jobs/job-passed.html"):
        again, page = await asyncio.to_thread(get, port, "attacker.example", path)
        assert again == 421 and b"job-passed" not in page


async def test_a_request_without_host_gets_no_run_data(port: int) -> None:
    status, body = await asyncio.to_thread(get, port, None)
    assert status == 400  # aiohttp refuses an HTTP/1.1 request without Host before our check
    assert b"job-passed" not in body
