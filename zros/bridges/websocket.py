"""The WebSocket side of rosbridge: accept clients, feed their frames to their sessions, and send
each one its frames through a bounded queue of its own.

A client that reads slowly (or not at all, a browser tab in the background) must neither stall
the others nor grow the bridge's memory: its frames wait in its own queue, drained by its own
writer task, and past `send_buffer_limit` bytes the oldest ones are dropped and counted (logged
once per burst). Frames of a subscription with a `queue_length` keep at most that many in the
queue, the newest, as rosbridge's queue_length asks.

The server runs an asyncio loop on a thread of its own (`WebSocketServer.start`); zros callbacks
reach a client from the executor's threads through `loop.call_soon_threadsafe`.
"""
from __future__ import annotations

import asyncio
import threading
from collections import deque
from typing import Any

from zros.bridges.rosbridge import Rosbridge

__all__ = ['WebSocketServer', 'ClientQueue', 'DEFAULT_SEND_BUFFER_LIMIT']

DEFAULT_SEND_BUFFER_LIMIT = 10_000_000   # [bytes] of frames waiting for one client


class ClientQueue:
    """Frames waiting for one client, bounded in bytes and per key; only the loop's thread
    touches it (`put` from elsewhere goes through `put_threadsafe`)."""

    def __init__(self, loop: asyncio.AbstractEventLoop, limit: int) -> None:
        self._loop = loop
        self.limit = limit
        self.frames: deque[tuple[Any, str | None]] = deque()
        self.size = 0          # [bytes] queued
        self.dropped = 0       # frames dropped, oldest first, since the client connected
        self.ready = asyncio.Event()

    def put_threadsafe(self, frame: Any, key: str | None = None, queue_length: int = 0) -> None:
        self._loop.call_soon_threadsafe(self.put, frame, key, queue_length)

    def put(self, frame: Any, key: str | None = None, queue_length: int = 0) -> None:
        if key is not None and queue_length > 0:
            same = [entry for entry in self.frames if entry[1] == key]
            for entry in same[:max(0, len(same) - queue_length + 1)]:
                self.frames.remove(entry)
                self.size -= len(entry[0])
                self.dropped += 1
        self.frames.append((frame, key))
        self.size += len(frame)
        while self.size > self.limit and len(self.frames) > 1:
            old, _ = self.frames.popleft()
            self.size -= len(old)
            self.dropped += 1
        self.ready.set()

    def take(self) -> Any | None:
        if not self.frames:
            self.ready.clear()
            return None
        frame, _ = self.frames.popleft()
        self.size -= len(frame)
        return frame


class WebSocketServer:
    """rosbridge's WebSocket endpoint on `address`:`port` (port 0: any free port, see `.port`).

    Args:
        bridge: the protocol state the sessions share.
        send_buffer_limit: bytes of frames kept for a client that does not read; older ones drop.
    """

    def __init__(self, bridge: Rosbridge, *, address: str = '', port: int = 9090,
                 send_buffer_limit: int = DEFAULT_SEND_BUFFER_LIMIT) -> None:
        self.bridge = bridge
        self.address = address
        self.port = port
        self.send_buffer_limit = send_buffer_limit
        self._loop: asyncio.AbstractEventLoop | None = None
        self._stop: asyncio.Event | None = None
        self._thread: threading.Thread | None = None
        self._started = threading.Event()
        self._error: BaseException | None = None

    def start(self, timeout: float = 10.0) -> int:
        """Listen, on a thread of its own; returns the port.

        Raises:
            OSError: the address cannot be bound (port in use, unknown address).
        """
        self._thread = threading.Thread(target=lambda: asyncio.run(self._main()), name='rosbridge websocket',
                                        daemon=True)
        self._thread.start()
        if not self._started.wait(timeout):
            raise OSError(f'the WebSocket server did not start within {timeout} s')
        if self._error is not None:
            raise self._error
        return self.port

    def stop(self) -> None:
        """Close every connection and stop listening. Idempotent."""
        if self._loop is not None and self._stop is not None and not self._loop.is_closed():
            self._loop.call_soon_threadsafe(self._stop.set)
        if self._thread is not None:
            self._thread.join(5.0)

    async def _main(self) -> None:
        from websockets.asyncio.server import serve
        self._loop = asyncio.get_running_loop()
        self._stop = asyncio.Event()
        try:
            # Frames up to twice max_message_size reach the session, which answers the too-large
            # ones with a status error; larger ones close the connection (code 1009) unread.
            server = await serve(self._serve_client, self.address or None, self.port,
                                 max_size=2 * self.bridge.max_message_size, ping_interval=None)
        except OSError as exc:
            self._error = exc
            self._started.set()
            return
        self.port = next(iter(server.sockets)).getsockname()[1]
        self._started.set()
        async with server:
            await self._stop.wait()

    async def _serve_client(self, websocket: Any) -> None:
        from websockets.exceptions import ConnectionClosed
        queue = ClientQueue(asyncio.get_running_loop(), self.send_buffer_limit)
        session = self.bridge.open_session(queue.put_threadsafe)
        logger = self.bridge.node.get_logger()
        peer = websocket.remote_address
        logger.info(f'Client connected. {self.bridge.sessions} clients total.')
        writer = asyncio.create_task(self._write(websocket, queue))
        try:
            async for frame in websocket:
                await asyncio.to_thread(session.handle, frame)
        except ConnectionClosed:
            pass
        finally:
            writer.cancel()
            session.close()
            if queue.dropped:
                logger.warn(f'client {peer}: {queue.dropped} frames were dropped (send buffer full)')
            logger.info(f'Client disconnected. {self.bridge.sessions} clients total.')

    @staticmethod
    async def _write(websocket: Any, queue: ClientQueue) -> None:
        from websockets.exceptions import ConnectionClosed
        try:
            while True:
                await queue.ready.wait()
                while (frame := queue.take()) is not None:
                    await websocket.send(frame)
        except ConnectionClosed:
            pass
