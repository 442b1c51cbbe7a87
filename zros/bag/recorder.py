"""`zros bag record`: subscribe to topics as raw payloads and write them to a bag.

In a zros bag, payloads are stored exactly as they arrived (no decode, no re-encode), so play
re-publishes the original bytes; for a rosbag2 (CDR) bag each one is decoded and re-encoded as
CDR on the recorder's thread. Samples are taken from Zenoh's threads into the subscriptions' queues and
written on the recorder's one thread (the MCAP writer is not thread-safe). Stopping (Ctrl-C,
SIGTERM, --max-duration) first drains what has already arrived, then finishes the file, so
every message received before the stop is in it.
"""
from __future__ import annotations

import sys
import threading
import time
from typing import Any, Callable

from zros.bag.definition import MESSAGE_ENCODING
from zros.bag.errors import BagError
from zros.graph_content import is_hidden

__all__ = ['Recorder', 'RECORDER_NODE_NAME']

RECORDER_NODE_NAME = 'zros_bag_recorder'


class Recorder:
    """Records `topics` (or every visible topic with `all_topics`) into `writer`.

    Args:
        context: an initialized zros Context (the recorder makes its own node in it).
        writer: a BagWriter; the recorder closes it when `run()` ends.
        topics: absolute topic names to record (they may appear later).
        all_topics: record every topic, including ones that appear while recording.
        include_hidden: with `all_topics`, also hidden topics (a `_` name part).
        log: where progress lines go (subscribed topics).
        stop_event: an event that stops `run()` when set (default: a private one; see `stop()`).
    """

    def __init__(self, context: Any, writer: Any, *, topics: list[str] | None = None, all_topics: bool = False,
                 include_hidden: bool = False, log: Callable[[str], None] | None = None,
                 stop_event: threading.Event | None = None) -> None:
        if not topics and not all_topics:
            raise BagError('nothing to record: give topic names or -a/--all')
        self._context = context
        self._writer = writer
        self._wanted = set(topics or ())
        self._all = all_topics
        self._include_hidden = include_hidden
        self._log = log or (lambda text: print(text, file=sys.stderr, flush=True))
        self._subscribed: dict[str, Any] = {}
        self._refused: set[str] = set()
        self._stop = stop_event or threading.Event()
        self._graph_changed = threading.Event()
        self._graph_changed.set()
        self._stop_ns: int | None = None
        self._past_stop: set[str] = set()

    @property
    def message_count(self) -> int:
        return self._writer.message_count

    def stop(self) -> None:
        """Ask `run()` to finish (safe from signal handlers and other threads)."""
        self._stop.set()

    def run(self, *, max_duration: float | None = None) -> None:
        """Record until `stop()` or `max_duration` seconds; always finishes the file."""
        from zros.executors import SingleThreadedExecutor
        from zros.node import Node
        node = Node(RECORDER_NODE_NAME, context=self._context, enable_rosout=False, use_global_arguments=False,
                    start_parameter_services=False)
        executor = SingleThreadedExecutor(context=self._context)
        executor.add_node(node)
        graph = self._context.graph
        graph.add_listener(self._graph_changed.set)
        deadline = None if max_duration is None else time.monotonic() + max_duration
        try:
            while not self._stop.is_set():
                if self._graph_changed.is_set():
                    self._graph_changed.clear()
                    self._subscribe_new(node, graph.entities())
                if deadline is not None and time.monotonic() >= deadline:
                    break
                wait = 0.1 if deadline is None else max(0.0, min(0.1, deadline - time.monotonic()))
                executor.spin_once(timeout_sec=wait)
            # Everything received before this instant goes into the bag; the subscriptions'
            # queues are FIFO, so a topic is drained once it yields a later sample or runs dry.
            self._stop_ns = time.time_ns()
            give_up = time.monotonic() + 5.0
            while time.monotonic() < give_up:
                pending = [name for name, sub in self._subscribed.items()
                           if name not in self._past_stop and sub._has_work()]
                if not pending:
                    break
                executor.spin_once(timeout_sec=0.01)
        finally:
            graph.remove_listener(self._graph_changed.set)
            for sub in list(self._subscribed.values()):
                node.destroy_subscription(sub)
            executor.remove_node(node)
            node.destroy_node()
            self._writer.close()

    def _encoder(self, topic: str, msg_type: type) -> Callable[[bytes], bytes | None]:
        """Payload bytes as the bag stores them: unchanged for a zros bag; CDR for a rosbag2
        one (None, with one warning per topic, for a payload that does not decode)."""
        if self._writer.encoding == MESSAGE_ENCODING:
            return lambda payload: payload
        from zros.errors import DecodeError
        from zros.message import deserialize
        codec = self._writer.codec
        warned = []

        def encode(payload: bytes) -> bytes | None:
            try:
                return codec.serialize(deserialize(payload, msg_type))
            except (DecodeError, BagError, ValueError, TypeError) as exc:
                if not warned:
                    warned.append(True)
                    self._log(f"[WARN] '{topic}': a message could not be converted to CDR, skipped ({exc})")
                return None
        return encode

    def _subscribe_new(self, node: Any, entities: list) -> None:
        from zros.graph import EntityKind
        from zros.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
        from zros.typesupport import get_message
        publishers: dict[str, list] = {}
        for e in entities:
            if e.kind == EntityKind.PUBLISHER:
                publishers.setdefault(e.name, []).append(e)
        for name, pubs in sorted(publishers.items()):
            if name in self._subscribed or name in self._refused:
                continue
            if not (name in self._wanted or (self._all and (self._include_hidden or not is_hidden(name)))):
                continue
            types = sorted({e.type for e in pubs})
            if len(types) > 1:
                self._refused.add(name)
                self._log(f"[WARN] not recording '{name}': it has more than one type ({', '.join(types)})")
                continue
            try:
                msg_type = get_message(types[0])
            except Exception as exc:  # noqa: BLE001 - an unknown type skips the topic, not the recording
                self._refused.add(name)
                self._log(f"[WARN] not recording '{name}': {exc}")
                continue
            offers = [QoSProfile.from_token(e.qos) for e in pubs]
            reliable = all(q.reliability == ReliabilityPolicy.RELIABLE for q in offers)
            transient = all(q.durability == DurabilityPolicy.TRANSIENT_LOCAL for q in offers)
            qos = QoSProfile(depth=10000,
                             reliability=ReliabilityPolicy.RELIABLE if reliable else ReliabilityPolicy.BEST_EFFORT,
                             durability=DurabilityPolicy.TRANSIENT_LOCAL if transient else DurabilityPolicy.VOLATILE)
            self._writer.add_topic(name, msg_type._TYPE, type_hash=msg_type._HASH, qos=pubs[0].qos)
            write = self._writer.write
            encode = self._encoder(name, msg_type)

            def on_message(payload: bytes, info: dict, _topic: str = name, _encode=encode) -> None:
                received = info['received_timestamp']
                if self._stop_ns is not None and received > self._stop_ns:
                    self._past_stop.add(_topic)
                    return
                data = _encode(payload)
                if data is not None:
                    write(_topic, data, log_time=received, publish_time=info['source_timestamp'] or received)
            self._subscribed[name] = node.create_subscription(msg_type, name, on_message, qos, raw=True)
            self._log(f"Subscribed to topic '{name}' ({msg_type._TYPE})")
