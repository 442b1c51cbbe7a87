"""launch.utilities.AsyncSafeSignalManager: signals handled as callbacks of an asyncio loop.

A plain `signal.signal` handler runs between two bytecodes of whatever the main thread is doing,
so it must not touch the event loop. This manager instead has Python's C-level handler write
the signal number to a socket (`signal.set_wakeup_fd`) that the loop reads, and calls the
registered handler from the loop, where it may set futures and schedule work. It leaves the
handlers installed with `signal.signal` alone (the signal is still delivered to them; a signal
whose disposition is SIG_DFL or SIG_IGN never reaches the wakeup fd at all).

Managers nest: each forwards what it reads to the wakeup fd that was set before it, so an inner
manager, asyncio's own `add_signal_handler` or zros.signals' watcher still see every signal.
While any manager is active, `signal.set_wakeup_fd` is redirected to the outermost one, so code
that sets a wakeup fd inside the context extends the chain instead of cutting it.

Unix only (zros runs on Linux and macOS); must be entered from the main thread.
"""
from __future__ import annotations

import asyncio
import os
import signal
import socket
import threading
from typing import Callable, ClassVar

__all__ = ['AsyncSafeSignalManager']

SignalHandler = Callable[[int], None]


class AsyncSafeSignalManager:
    """`with AsyncSafeSignalManager(loop) as manager:` then `manager.handle(signal.SIGINT, f)`;
    `f(signum)` runs in `loop` for each SIGINT while the context is active. Handlers may be
    registered before, inside or between contexts, and the context may be entered again.

    Args:
        loop: the event loop that calls the handlers (it must be able to watch a socket).
    """

    _innermost: ClassVar[AsyncSafeSignalManager | None] = None
    _set_wakeup_fd: ClassVar[Callable[..., int]] = staticmethod(signal.set_wakeup_fd)

    def __init__(self, loop: asyncio.AbstractEventLoop) -> None:
        self._loop = loop
        self._handlers: dict[int, SignalHandler] = {}
        self._outer: AsyncSafeSignalManager | None = None
        self._forward_fd = -1           # the wakeup fd set before ours: signals are passed on
        self._reader: socket.socket | None = None
        self._writer: socket.socket | None = None

    def handle(self, signum: int, handler: SignalHandler | None) -> SignalHandler | None:
        """Call `handler(signum)` for `signum` (None: stop handling it); returns the previous one.

        Raises:
            ValueError: `signum` is not a signal, or `handler` is not callable.
        """
        signum = signal.Signals(signum)
        if handler is None:
            return self._handlers.pop(signum, None)
        if not callable(handler):
            raise ValueError('a signal handler must be callable')
        previous = self._handlers.get(signum)
        self._handlers[signum] = handler
        return previous

    def __enter__(self) -> AsyncSafeSignalManager:
        if threading.current_thread() is not threading.main_thread():
            raise ValueError('AsyncSafeSignalManager works only in the main thread')
        self._reader, self._writer = socket.socketpair()
        self._reader.setblocking(False)
        self._writer.setblocking(False)
        self._loop.add_reader(self._reader.fileno(), self._drain)
        try:
            self._forward_fd = AsyncSafeSignalManager._set_wakeup_fd(self._writer.fileno())
        except BaseException:
            self._close()
            raise
        self._outer, AsyncSafeSignalManager._innermost = AsyncSafeSignalManager._innermost, self
        if self._outer is None:
            signal.set_wakeup_fd = self._extend_chain   # type: ignore[assignment]
        return self

    def __exit__(self, *exc_info: object) -> None:
        try:
            own = AsyncSafeSignalManager._set_wakeup_fd(self._forward_fd)
            assert self._writer is not None and own == self._writer.fileno(), 'the signal wakeup chain was broken'
        finally:
            if self._outer is None:
                signal.set_wakeup_fd = AsyncSafeSignalManager._set_wakeup_fd  # type: ignore[assignment]
            AsyncSafeSignalManager._innermost = self._outer
            self._outer, self._forward_fd = None, -1
            self._close()

    def _extend_chain(self, fd: int, **_options: object) -> int:
        """`signal.set_wakeup_fd` while managers are active: `fd` becomes the last link."""
        if threading.current_thread() is not threading.main_thread():
            raise ValueError('set_wakeup_fd only works in the main thread of the main interpreter')
        previous, self._forward_fd = self._forward_fd, fd
        return previous

    def _drain(self) -> None:
        """Read the signal numbers the C handler wrote; call handlers and pass them on."""
        assert self._reader is not None
        while True:
            try:
                data = self._reader.recv(4096)
            except InterruptedError:
                continue
            except BlockingIOError:
                return
            if not data:
                return
            for signum in data:
                handler = self._handlers.get(signum)
                if handler is not None:
                    handler(signum)
            if self._forward_fd != -1:
                try:
                    os.write(self._forward_fd, data)
                except OSError:
                    pass  # a full or closed downstream pipe loses signals, as Python's own does

    def _close(self) -> None:
        if self._reader is not None:
            self._loop.remove_reader(self._reader.fileno())
            self._reader.close()
        if self._writer is not None:
            self._writer.close()
        self._reader = self._writer = None
