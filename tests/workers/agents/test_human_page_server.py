"""The human agent's page server: a page that connects while the harness moves on still ends up with the
harness's latest status (a page shown "wait" while the harness waits for the person stalls the episode)."""

from __future__ import annotations

import asyncio
import base64
import json
import os
import struct

from workers.agents._human._events import PageMessage, Progress, TaskShown
from workers.agents._human._server import PageServer

FRAME_BYTES = 32 * 2**20
"""A live frame larger than the kernel's and both ends' buffers can hold: its send waits for the page."""


async def read_frame(reader: asyncio.StreamReader) -> tuple[int, bytes]:
    """One unmasked websocket frame from the server: its opcode and payload."""
    first, second = await reader.readexactly(2)
    length = second & 0x7F
    if length == 126:
        (length,) = struct.unpack("!H", await reader.readexactly(2))
    elif length == 127:
        (length,) = struct.unpack("!Q", await reader.readexactly(8))
    return first & 0x0F, await reader.readexactly(length)


async def connect(port: int) -> tuple[asyncio.StreamReader, asyncio.StreamWriter]:
    """A websocket handshake by hand, so that the test decides when the page reads."""
    reader, writer = await asyncio.open_connection("127.0.0.1", port)
    key = base64.b64encode(os.urandom(16)).decode()
    writer.write(
        (
            f"GET /ws HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
            f"Sec-WebSocket-Key: {key}\r\nSec-WebSocket-Version: 13\r\n\r\n"
        ).encode()
    )
    await writer.drain()
    assert (await reader.readuntil(b"\r\n\r\n")).startswith(b"HTTP/1.1 101")
    return reader, writer


async def test_a_status_sent_while_a_page_is_greeted_reaches_it() -> None:
    received: list[PageMessage] = []
    presence = asyncio.Queue[int]()
    server = PageServer(0, received.append, presence.put_nowait)
    server.greeting = TaskShown(
        task_id="t", instruction="i", mode="primitive", max_steps=5, participant="p", started_at=0.0,
        viewport={"width": 1280, "height": 720},
    )  # fmt: skip
    server.latest_frame = os.urandom(FRAME_BYTES)
    await server.start()
    try:
        reader, writer = await connect(server.port)
        greeting, status = await read_frame(reader), await read_frame(reader)
        assert json.loads(greeting[1])["type"] == "task" and json.loads(status[1])["ready"] is False
        # The page reads no further: the server is still sending it the frame when the harness turns ready.
        server.send(Progress(steps=0, ready=True))
        opcode, frame = await read_frame(reader)
        assert (opcode, len(frame)) == (0x2, FRAME_BYTES)
        opcode, payload = await read_frame(reader)
        assert opcode == 0x1 and json.loads(payload) == {"type": "status", "steps": 0, "ready": True}
        assert await presence.get() == 1
        writer.close()
        await writer.wait_closed()
    finally:
        await server.stop()
