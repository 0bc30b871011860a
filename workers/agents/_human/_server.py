"""The person's page, served on 127.0.0.1 (reach it from a laptop over ``ssh -L``): the editor live, the task,
a timer, Submit and Give up. One websocket per open page carries frames out and input in.

Frames go out as binary messages, everything else as JSON; a page still sending the previous frame skips the
next one rather than queueing it (the live view stays live on a slow tunnel).
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Callable
from importlib.resources import files
from typing import Any

from aiohttp import WSMsgType, web
from pydantic import BaseModel, TypeAdapter, ValidationError

from workers._held_tasks import HeldTasks, hold
from workers.agents._human._events import PageMessage, Progress, TaskShown

log = logging.getLogger(__name__)

HOST = "127.0.0.1"
_MESSAGES: TypeAdapter[PageMessage] = TypeAdapter(PageMessage)


class PageServer:
    """Serves the page; ``on_message`` gets each valid message, ``on_presence`` the number of open pages."""

    def __init__(
        self,
        port: int,
        on_message: Callable[[PageMessage], None],
        on_presence: Callable[[int], None],
    ) -> None:
        self.port = port
        self.on_message = on_message
        self.on_presence = on_presence
        self.greeting: TaskShown | None = None
        """The first message every page gets; ``status`` follows it."""

        self.status = Progress()
        self.latest_frame: bytes | None = None
        self._sockets: dict[web.WebSocketResponse, asyncio.Task[Any] | None] = {}
        self._runner: web.AppRunner | None = None
        self._sends: HeldTasks = set()

    @property
    def url(self) -> str:
        return f"http://{HOST}:{self.port}/"

    async def start(self) -> None:
        app = web.Application()
        app.router.add_get("/", self._index)
        app.router.add_get("/ws", self._socket)
        self._runner = web.AppRunner(app, access_log=None)
        await self._runner.setup()
        site = web.TCPSite(self._runner, HOST, self.port)
        try:
            await site.start()
        except OSError as exc:
            await self._runner.cleanup()
            raise OSError(f"the human agent's page cannot listen on {HOST}:{self.port}: {exc.strerror}") from exc
        self.port = self._runner.addresses[0][1]

    async def stop(self) -> None:
        await asyncio.gather(*self._sends, return_exceptions=True)  # the last word ("ended") reaches every page
        for socket in list(self._sockets):
            await socket.close()
        if self._runner is not None:
            await self._runner.cleanup()
            self._runner = None

    def send_frame(self, frame: bytes) -> None:
        self.latest_frame = frame
        for socket, sending in list(self._sockets.items()):
            if sending is None or sending.done():
                self._sockets[socket] = asyncio.ensure_future(self._send(socket, frame))

    def send(self, message: BaseModel) -> None:
        """A JSON message to every open page (``Progress`` is also kept for pages that open later)."""
        if isinstance(message, Progress):
            self.status = message
        for socket in list(self._sockets):
            hold(self._send(socket, message.model_dump_json()), self._sends)

    @staticmethod
    async def _send(socket: web.WebSocketResponse, data: bytes | str) -> None:
        if socket.closed:
            return
        try:
            if isinstance(data, bytes):
                await socket.send_bytes(data)
            else:
                await socket.send_str(data)
        except (ConnectionError, RuntimeError):
            pass  # the page closed meanwhile: its socket handler notices

    async def _index(self, request: web.Request) -> web.Response:
        page = files("workers.agents._human").joinpath("page.html").read_text(encoding="utf-8")
        return web.Response(text=page, content_type="text/html", headers={"Cache-Control": "no-store"})

    async def _socket(self, request: web.Request) -> web.WebSocketResponse:
        socket = web.WebSocketResponse(heartbeat=10)
        await socket.prepare(request)
        if self.greeting is not None:
            await socket.send_str(self.greeting.model_dump_json())
        status: Progress | None = None
        frame: bytes | None = None
        while status is not self.status or frame is not self.latest_frame:  # again if either changed meanwhile
            if status is not self.status:
                status = self.status
                await socket.send_str(status.model_dump_json())
            if frame is not self.latest_frame:
                frame = self.latest_frame
                if frame is not None:
                    await socket.send_bytes(frame)
        self._sockets[socket] = None  # from here on, every status and frame reaches this page as it is sent
        self.on_presence(len(self._sockets))
        try:
            async for message in socket:
                if message.type != WSMsgType.TEXT:
                    continue
                try:
                    parsed = _MESSAGES.validate_json(message.data)
                except ValidationError as exc:
                    log.warning("the human page sent an unusable message: %s", exc.errors()[0]["msg"])
                    continue
                self.on_message(parsed)
        finally:
            self._sockets.pop(socket, None)
            self.on_presence(len(self._sockets))
        return socket
