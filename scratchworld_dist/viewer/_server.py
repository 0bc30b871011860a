"""The viewer's local web server: the site's paths over HTTP on 127.0.0.1 (aiohttp).

Pages are built on each request, so a refresh shows a run in progress as it stands. It listens
on the loopback interface only and opens no browser by itself, and it answers only requests addressed
to a loopback name: a page elsewhere that rebinds its own DNS name to 127.0.0.1 sends that name as
``Host`` and is refused, so it cannot read a run (DNS rebinding).
"""

from __future__ import annotations

import asyncio
import re
from collections.abc import Awaitable, Callable

from aiohttp import web

from scratchworld_dist.viewer._site import ViewerSite

HOST = "127.0.0.1"
LOOPBACK_HOST = re.compile(r"(127\.0\.0\.1|localhost|\[::1\])(:[0-9]{1,5})?", re.IGNORECASE)
"""The ``Host`` values a browser on this machine sends: a loopback name, with any port (a tunnel may
forward another port to ours)."""

REFUSED_HOST = "this viewer answers only to 127.0.0.1, localhost and [::1]\n"


@web.middleware
async def loopback_host_only(
    request: web.Request, handler: Callable[[web.Request], Awaitable[web.StreamResponse]]
) -> web.StreamResponse:
    """421 for a request whose ``Host`` header is missing or names anything but this machine's loopback."""
    if LOOPBACK_HOST.fullmatch(request.headers.get("Host", "")) is None:
        return web.Response(status=421, text=REFUSED_HOST)
    return await handler(request)


def viewer_app(site: ViewerSite) -> web.Application:
    async def handle(request: web.Request) -> web.StreamResponse:
        # Pages read Parquet and render templates: off the event loop, so one slow page blocks no other.
        resource = await asyncio.to_thread(site.get, request.match_info["path"])
        if resource is None:
            raise web.HTTPNotFound(text="no such page in this viewer")
        if resource.file is not None:
            return web.FileResponse(resource.file, headers={"Content-Type": resource.content_type})
        return web.Response(body=resource.body, headers={"Content-Type": resource.content_type})

    app = web.Application(middlewares=[loopback_host_only])
    app.router.add_get("/{path:.*}", handle)
    return app


async def serve(site: ViewerSite, port: int, ready: Callable[[str], Awaitable[None] | None]) -> None:
    """Serve until cancelled; ``ready(url)`` is called once the port is bound (``port`` 0: a free one)."""
    runner = web.AppRunner(viewer_app(site), access_log=None)
    await runner.setup()
    try:
        listener = web.TCPSite(runner, HOST, port)
        await listener.start()
        bound = runner.addresses[0][1]
        announced = ready(f"http://{HOST}:{bound}/")
        if announced is not None:
            await announced
        await asyncio.Event().wait()
    finally:
        await runner.cleanup()
