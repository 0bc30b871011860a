"""The viewer's local web server: the site's paths over HTTP on 127.0.0.1 (aiohttp).

Pages are built on each request, so a refresh shows a run in progress as it stands. It listens
on the loopback interface only and opens no browser by itself.
"""

from __future__ import annotations

import asyncio
from collections.abc import Awaitable, Callable

from aiohttp import web

from scratchworld_dist.viewer._site import ViewerSite

HOST = "127.0.0.1"


def viewer_app(site: ViewerSite) -> web.Application:
    async def handle(request: web.Request) -> web.StreamResponse:
        # Pages read Parquet and render templates: off the event loop, so one slow page blocks no other.
        resource = await asyncio.to_thread(site.get, request.match_info["path"])
        if resource is None:
            raise web.HTTPNotFound(text="no such page in this viewer")
        if resource.file is not None:
            return web.FileResponse(resource.file, headers={"Content-Type": resource.content_type})
        return web.Response(body=resource.body, headers={"Content-Type": resource.content_type})

    app = web.Application()
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
