"""The web view's HTTP server: image topics of the graph, shown live in a browser.

Standard library only (`http.server.ThreadingHTTPServer`); the page, its script and its style
ship in `zros/view/static/`, so nothing is fetched from the internet. Endpoints:

    GET /                         the page (`?topic=/name` preselects a topic)
    GET /static/<file>            the page's script and style
    GET /api/topics               {"topics": [{"name", "type"}], "default": name | null}
    GET /frame.png?topic=T        the newest frame of T as PNG; with `after=N` it waits (long
                                  poll, `timeout` s, at most 10) for a frame newer than
                                  sequence number N; 204 when none came. Headers X-Frame-Seq,
                                  X-Frame-Width, X-Frame-Height, X-Frame-Encoding.
    GET /stream?topic=T           the frames as multipart/x-mixed-replace PNGs (for <img>)

A topic is subscribed (best effort, like ROS's sensor-data profile) when a client first asks
for it and unsubscribed after `idle_timeout` seconds without a request, so a publisher that
only publishes while someone listens (turtlesim's canvas) stops when the page closes.
Each frame is encoded to PNG at most once, whatever the number of clients.
"""
from __future__ import annotations

import html
import json
import threading
import time
from http import HTTPStatus
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from typing import TYPE_CHECKING, Any
from urllib.parse import parse_qs, urlsplit

from zros.view.image import UnsupportedEncoding, image_to_array
from zros.image_io import encode_png

if TYPE_CHECKING:
    from zros.node import Node

__all__ = ['ViewServer', 'FrameStore', 'Frame', 'IMAGE_TYPE', 'DEFAULT_PORT', 'PREFERRED_TOPIC']

IMAGE_TYPE = 'sensor_msgs/msg/Image'
DEFAULT_PORT = 8080
PREFERRED_TOPIC = '/turtlesim/image'   # the default when it exists and none was asked for
STATIC_DIR = Path(__file__).resolve().parent / 'static'
_STATIC_TYPES = {'.html': 'text/html; charset=utf-8', '.js': 'text/javascript; charset=utf-8',
                 '.css': 'text/css; charset=utf-8', '.png': 'image/png', '.svg': 'image/svg+xml'}
_MAX_WAIT = 10.0


class Frame:
    """One received image: sequence number, message, and its PNG once somebody needed it."""

    __slots__ = ('seq', 'msg', 'received', '_png', '_error', '_lock')

    def __init__(self, seq: int, msg: Any) -> None:
        self.seq, self.msg, self.received = seq, msg, time.monotonic()
        self._png: bytes | None = None
        self._error: str | None = None
        self._lock = threading.Lock()

    def png(self) -> bytes:
        """The frame as PNG (encoded on first use); UnsupportedEncoding if it can't be shown."""
        with self._lock:
            if self._png is None and self._error is None:
                try:
                    self._png = encode_png(image_to_array(self.msg), level=3)
                except UnsupportedEncoding as exc:
                    self._error = str(exc)
            if self._error is not None:
                raise UnsupportedEncoding(self._error)
            return self._png  # type: ignore[return-value]


class _Topic:
    def __init__(self) -> None:
        self.subscription: Any = None
        self.frame: Frame | None = None
        self.last_used = time.monotonic()


class FrameStore:
    """The newest frame of each image topic a client asked for, subscribed on demand.

    Thread contract: HTTP handler threads call `wait_frame` and `image_topics`; the node's
    executor calls the subscription callbacks. `close()` wakes every waiter.
    """

    def __init__(self, node: 'Node', *, idle_timeout: float = 30.0) -> None:
        self._node = node
        self._idle_timeout = idle_timeout
        self._topics: dict[str, _Topic] = {}
        self._cond = threading.Condition()
        self._closed = False

    def image_topics(self) -> list[str]:
        """Every topic in the graph that carries sensor_msgs/msg/Image, sorted."""
        return sorted(name for name, types in self._node.get_topic_names_and_types() if IMAGE_TYPE in types)

    def wait_frame(self, topic: str, after: int = 0, timeout: float = 2.0) -> Frame | None:
        """The newest frame of `topic` whose seq is greater than `after`, waiting up to
        `timeout` s for one; None if none came. Subscribes on first use.

        Raises:
            zros.errors.InvalidNameError: `topic` is not a valid topic name.
        """
        deadline = time.monotonic() + max(0.0, min(timeout, _MAX_WAIT))
        entry = self._entry(topic)
        with self._cond:
            while not self._closed:
                entry.last_used = time.monotonic()
                frame = entry.frame
                if frame is not None and frame.seq > after:
                    return frame
                remaining = deadline - time.monotonic()
                if remaining <= 0:
                    return None
                self._cond.wait(remaining)
        return None

    def _entry(self, topic: str) -> _Topic:
        from interfaces.sensor_msgs.msg import Image
        from zros.qos import qos_profile_sensor_data
        self._expire_idle()
        with self._cond:
            entry = self._topics.get(topic)
            if entry is not None:
                return entry
            entry = _Topic()
            self._topics[topic] = entry
        try:
            entry.subscription = self._node.create_subscription(
                Image, topic, lambda msg: self._on_image(entry, msg), qos_profile_sensor_data)
        except Exception:
            with self._cond:
                self._topics.pop(topic, None)
            raise
        return entry

    def _on_image(self, entry: _Topic, msg: Any) -> None:
        with self._cond:
            seq = entry.frame.seq + 1 if entry.frame is not None else 1
            entry.frame = Frame(seq, msg)
            self._cond.notify_all()

    def _expire_idle(self) -> None:
        now = time.monotonic()
        with self._cond:
            idle = [(name, entry) for name, entry in self._topics.items()
                    if entry.subscription is not None and now - entry.last_used > self._idle_timeout]
            for name, _ in idle:
                del self._topics[name]
        for _, entry in idle:
            self._node.destroy_subscription(entry.subscription)

    @property
    def closed(self) -> bool:
        return self._closed

    def close(self) -> None:
        with self._cond:
            self._closed = True
            entries = list(self._topics.values())
            self._topics.clear()
            self._cond.notify_all()
        for entry in entries:
            if entry.subscription is not None:
                try:
                    self._node.destroy_subscription(entry.subscription)
                except Exception:  # noqa: BLE001 - the node may be gone already
                    pass


class ViewServer:
    """Serves the view for `node`'s graph on http://host:port/. The caller spins the node.

    Args:
        node: the node whose context's graph is listed and which subscribes to the images.
        host: address to bind; loopback by default, so nothing is exposed to the network.
        port: TCP port; 0 picks a free one. If it is taken, the next `port_tries - 1` ports
            are tried.
        topic: the topic the page shows first (default: /turtlesim/image if present, else the
            first image topic).
    Raises:
        OSError: no port could be bound.
    """

    def __init__(self, node: 'Node', *, host: str = '127.0.0.1', port: int = DEFAULT_PORT,
                 topic: str | None = None, port_tries: int = 1, idle_timeout: float = 30.0) -> None:
        self.node = node
        self.store = FrameStore(node, idle_timeout=idle_timeout)
        self.default_topic = topic or None
        handler = _make_handler(self)
        last_error: OSError | None = None
        for candidate in ([port] if port == 0 else range(port, port + max(1, port_tries))):
            try:
                self._httpd = ThreadingHTTPServer((host, candidate), handler)
                break
            except OSError as exc:
                last_error = exc
        else:
            raise OSError(f'cannot serve on {host}:{port}'
                          + (f'..{port + port_tries - 1}' if port_tries > 1 else '') + f': {last_error}')
        self._httpd.daemon_threads = True
        self.host = host
        self.port = self._httpd.server_address[1]
        self._thread: threading.Thread | None = None

    @property
    def url(self) -> str:
        host = {'0.0.0.0': '127.0.0.1', '': '127.0.0.1', '::': '[::1]'}.get(self.host, self.host)
        if ':' in host and not host.startswith('['):
            host = f'[{host}]'
        return f'http://{host}:{self.port}/'

    def page_url(self, topic: str | None = None) -> str:
        from urllib.parse import quote
        topic = topic or self.default_topic
        return self.url + (f'?topic={quote(topic)}' if topic else '')

    def pick_default(self) -> str | None:
        if self.default_topic:
            return self.default_topic
        topics = self.store.image_topics()
        if PREFERRED_TOPIC in topics:
            return PREFERRED_TOPIC
        return topics[0] if topics else None

    def start(self) -> 'ViewServer':
        self._thread = threading.Thread(target=self._httpd.serve_forever, kwargs={'poll_interval': 0.2},
                                        name='zros-view-http', daemon=True)
        self._thread.start()
        return self

    def close(self) -> None:
        """Stop serving (idempotent); open streams end within a second."""
        self.store.close()
        thread, self._thread = self._thread, None
        if thread is not None:
            self._httpd.shutdown()
            thread.join(timeout=2.0)
        self._httpd.server_close()

    def __enter__(self) -> 'ViewServer':
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.close()


def _make_handler(server: ViewServer) -> type[BaseHTTPRequestHandler]:
    store = server.store

    class Handler(BaseHTTPRequestHandler):
        server_version = 'zros-view/1'
        protocol_version = 'HTTP/1.1'

        def log_message(self, format: str, *args: Any) -> None:  # noqa: A002 - stdlib's name
            pass  # quiet: the terminal belongs to the node's log

        def do_GET(self) -> None:  # noqa: N802 - stdlib's name
            url = urlsplit(self.path)
            query = {k: v[-1] for k, v in parse_qs(url.query).items()}
            try:
                if url.path in ('/', '/index.html'):
                    self._page(query.get('topic') or server.pick_default())
                elif url.path.startswith('/static/'):
                    self._static(url.path[len('/static/'):])
                elif url.path == '/api/topics':
                    self._json({'topics': [{'name': t, 'type': IMAGE_TYPE} for t in store.image_topics()],
                                'default': server.pick_default()})
                elif url.path == '/frame.png':
                    self._frame(query)
                elif url.path == '/stream':
                    self._stream(query)
                elif url.path == '/favicon.ico':
                    self._send(HTTPStatus.NO_CONTENT, b'', 'image/x-icon')
                else:
                    self._text(HTTPStatus.NOT_FOUND, f'no such page: {url.path}')
            except (BrokenPipeError, ConnectionResetError):
                pass

        # -- responses ---------------------------------------------------------------------
        def _send(self, status: int, body: bytes, content_type: str, headers: dict[str, str] | None = None) -> None:
            self.send_response(status)
            self.send_header('Content-Type', content_type)
            self.send_header('Content-Length', str(len(body)))
            self.send_header('Cache-Control', 'no-store')
            for name, value in (headers or {}).items():
                self.send_header(name, value)
            self.end_headers()
            if body:
                self.wfile.write(body)

        def _text(self, status: int, text: str) -> None:
            self._send(status, text.encode(), 'text/plain; charset=utf-8')

        def _json(self, value: Any) -> None:
            self._send(HTTPStatus.OK, json.dumps(value).encode(), 'application/json')

        def _page(self, topic: str | None) -> None:
            template = (STATIC_DIR / 'index.html').read_text(encoding='utf-8')
            # The first frame is the <img>'s own src, so the page's load event (and a headless
            # browser's screenshot) waits for it; the script takes over from there.
            src = f'frame.png?topic={_quote(topic)}&timeout=3' if topic else ''
            page = (template.replace('__INITIAL_SRC__', html.escape(src, quote=True))
                    .replace('__INITIAL_TOPIC__', html.escape(json.dumps(topic), quote=True)))
            self._send(HTTPStatus.OK, page.encode(), _STATIC_TYPES['.html'])

        def _static(self, name: str) -> None:
            path = (STATIC_DIR / name).resolve()
            if path.parent != STATIC_DIR or not path.is_file() or path.suffix not in _STATIC_TYPES:
                self._text(HTTPStatus.NOT_FOUND, f'no such file: {name}')
                return
            self._send(HTTPStatus.OK, path.read_bytes(), _STATIC_TYPES[path.suffix])

        def _topic(self, query: dict[str, str]) -> str | None:
            topic = query.get('topic') or server.pick_default()
            if not topic:
                self._text(HTTPStatus.NOT_FOUND, 'no image topic: none was given and the graph has none')
                return None
            return topic if topic.startswith('/') else '/' + topic

        def _frame(self, query: dict[str, str]) -> None:
            topic = self._topic(query)
            if topic is None:
                return
            try:
                after = int(query.get('after', '0'))
                timeout = float(query.get('timeout', '2'))
                frame = store.wait_frame(topic, after, timeout)
            except ValueError as exc:  # bad numbers, or an invalid topic name
                self._text(HTTPStatus.BAD_REQUEST, str(exc))
                return
            if frame is None:
                self._send(HTTPStatus.NO_CONTENT, b'', 'image/png')
                return
            try:
                body = frame.png()
            except UnsupportedEncoding as exc:
                self._text(HTTPStatus.UNSUPPORTED_MEDIA_TYPE, str(exc))
                return
            self._send(HTTPStatus.OK, body, 'image/png', {
                'X-Frame-Seq': str(frame.seq), 'X-Frame-Width': str(frame.msg.width),
                'X-Frame-Height': str(frame.msg.height), 'X-Frame-Encoding': frame.msg.encoding})

        def _stream(self, query: dict[str, str]) -> None:
            topic = self._topic(query)
            if topic is None:
                return
            self.close_connection = True
            self.send_response(HTTPStatus.OK)
            self.send_header('Content-Type', 'multipart/x-mixed-replace; boundary=zrosframe')
            self.send_header('Cache-Control', 'no-store')
            self.send_header('Connection', 'close')
            self.end_headers()
            seq = 0
            while not store.closed:
                try:
                    frame = store.wait_frame(topic, seq, 1.0)
                except ValueError:
                    return
                if frame is None:
                    continue
                seq = frame.seq
                try:
                    body = frame.png()
                except UnsupportedEncoding:
                    return
                self.wfile.write(b'--zrosframe\r\nContent-Type: image/png\r\n'
                                 + f'Content-Length: {len(body)}\r\n\r\n'.encode() + body + b'\r\n')
                self.wfile.flush()

    return Handler


def _quote(text: str) -> str:
    from urllib.parse import quote
    return quote(text, safe='/')
