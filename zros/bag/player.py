"""`zros bag play`: re-publish a bag's payloads with their recorded timing.

Messages go out in log-time order; message k is sent at `start + (t_k - t_0) / rate` on the
monotonic clock, so inter-message gaps match the recording (scaled by `rate`) and do not drift.
A zros bag's payloads are published unchanged; a ROS 2 bag's CDR payloads are decoded
(zros.bag.cdr) and published as zros messages, so a rosbag2 recording from a real robot replays
into zros. With `clock_hz`, `/clock`
(rosgraph_msgs/msg/Clock) carries the bag's time at that rate, so `use_sim_time` nodes follow
the recording.
"""
from __future__ import annotations

import sys
import threading
import time
from typing import Any, Callable

from zros.bag.cdr import CDR_ENCODING, CdrCodec
from zros.bag.errors import BagError

__all__ = ['Player', 'PLAYER_NODE_NAME', 'raw_publisher']

PLAYER_NODE_NAME = 'zros_bag_player'


def raw_publisher(publisher: Any) -> Callable[[bytes], None]:
    """A function that publishes already-encoded payload bytes through `publisher` (rclpy's
    serialized publish), with a fresh attachment: its gid, next sequence number, current time."""
    return publisher.publish


class Player:
    """Plays the bag at `path` through publishers of its own node.

    Args:
        context: an initialized zros Context.
        path: the bag directory or .mcap file.
        rate: playback speed factor (2.0 plays twice as fast).
        loop: start again from the beginning at the end.
        topics: only these topics (absolute names); default all.
        clock_hz: publish /clock at this rate (None: don't).
        delay: seconds to wait after creating the publishers, before the first message.
        start_offset: skip this many seconds from the beginning of the bag.
        log: where progress lines go.
        stop_event: an event that stops `run()` when set (default: a private one; see `stop()`).
    Raises:
        BagError: the bag cannot be read, or `rate` is not positive.
    """

    def __init__(self, context: Any, path: str, *, rate: float = 1.0, loop: bool = False,
                 topics: list[str] | None = None, clock_hz: float | None = None, delay: float = 0.0,
                 start_offset: float = 0.0, log: Callable[[str], None] | None = None,
                 stop_event: threading.Event | None = None) -> None:
        from zros.bag.reader import open_bag
        if rate <= 0:
            raise BagError('--rate must be > 0')
        if clock_hz is not None and clock_hz <= 0:
            raise BagError('--clock rate must be > 0')
        self._context = context
        self._reader = open_bag(path)
        self._summary = self._reader.summary()
        self._rate = rate
        self._loop = loop
        self._clock_hz = clock_hz
        self._delay = max(0.0, delay)
        self._offset_ns = int(max(0.0, start_offset) * 1e9)
        self._log = log or (lambda text: print(text, file=sys.stderr, flush=True))
        known = {t.name for t in self._summary.topics}
        if topics:
            missing = [t for t in topics if t not in known]
            if missing:
                raise BagError(f"topic(s) not in the bag: {', '.join(missing)}")
        self._topics = list(topics) if topics else sorted(known)
        self._stop = stop_event or threading.Event()
        self.published = 0
        #: topic -> CDR messages skipped because they did not decode
        self.undecodable: dict[str, int] = {}
        self._codec: CdrCodec | None = None

    def stop(self) -> None:
        self._stop.set()

    def run(self) -> int:
        """Play (once, or until stopped with `loop`); returns the number of messages published."""
        from zros.node import Node
        node = Node(PLAYER_NODE_NAME, context=self._context, enable_rosout=False, use_global_arguments=False,
                    start_parameter_services=False)
        try:
            senders = self._make_publishers(node)
            clock = self._make_clock(node) if self._clock_hz else None
            self._wait_for_links(node)
            if self._delay:
                self._stop.wait(self._delay)
            while not self._stop.is_set():
                self._play_once(senders, clock)
                if not self._loop:
                    break
        finally:
            node.destroy_node()
        return self.published

    # -- set-up -------------------------------------------------------------------------------
    def _make_publishers(self, node: Any) -> dict[str, Callable[[bytes], None]]:
        from zros.bag.definition import MESSAGE_ENCODING
        from zros.qos import DurabilityPolicy, HistoryPolicy, QoSProfile
        from zros.typesupport import get_message
        senders = {}
        for info in self._summary.topics:
            if info.name not in self._topics:
                continue
            if info.encoding not in (MESSAGE_ENCODING, CDR_ENCODING):
                self._log(f"[WARN] not playing '{info.name}': its messages are encoded as '{info.encoding}', "
                          f'which zros cannot decode ({MESSAGE_ENCODING} and {CDR_ENCODING} can be played)')
                continue
            try:
                msg_type = get_message(info.type)
            except Exception as exc:  # noqa: BLE001 - an unknown type skips that topic
                self._log(f"[WARN] not playing '{info.name}': {exc}")
                continue
            recorded = QoSProfile.from_token(info.qos)
            qos = QoSProfile(depth=max(recorded.queue_depth, 10) if recorded.history == HistoryPolicy.KEEP_LAST else 10,
                             reliability=recorded.reliability,
                             durability=recorded.durability if recorded.durability == DurabilityPolicy.TRANSIENT_LOCAL
                             else DurabilityPolicy.VOLATILE)
            publisher = node.create_publisher(msg_type, info.name, qos)
            if info.encoding == CDR_ENCODING:
                senders[info.name] = self._cdr_sender(info, msg_type, publisher)
                continue
            if info.type_hash and info.type_hash != msg_type._HASH:
                self._log(f"[WARN] '{info.name}': the definition of {info.type} changed since the recording "
                          f'(hash {info.type_hash}, now {msg_type._HASH}); subscribers may reject it')
            senders[info.name] = raw_publisher(publisher)
        return senders

    def _cdr_sender(self, info: Any, msg_type: type, publisher: Any) -> Callable[[bytes], None]:
        """Decodes each CDR payload with zros's definition of the type and publishes it; a payload
        that does not decode is skipped (one warning per topic, the count at the end)."""
        if self._codec is None:
            self._codec = CdrCodec()
        codec = self._codec
        ours = codec.rihs01(info.type)
        if info.type_hash.startswith('RIHS01_') and info.type_hash != ours:
            self._log(f"[WARN] '{info.name}': the bag's definition of {info.type} differs from zros's "
                      f'({info.type_hash} vs {ours}); decoding with zros\'s may fail')

        def send(data: bytes) -> None:
            try:
                msg = codec.deserialize(data, msg_type)
            except BagError as exc:
                if info.name not in self.undecodable:
                    self._log(f"[WARN] '{info.name}': skipping messages that do not decode: {exc}")
                self.undecodable[info.name] = self.undecodable.get(info.name, 0) + 1
                return
            publisher.publish(msg)
        return send

    def _make_clock(self, node: Any) -> Any:
        from zros.typesupport import get_message
        from zros.qos import QoSProfile
        clock_type = get_message('rosgraph_msgs/msg/Clock')
        return node.create_publisher(clock_type, '/clock', QoSProfile(depth=1)), clock_type

    def _wait_for_links(self, node: Any, timeout: float = 2.0) -> None:
        """Give subscribers that are already running a direct link to this process before the
        first message, so a fresh player does not send its first messages to nobody."""
        from zros.graph import EntityKind
        session = self._context.session
        deadline = time.monotonic() + timeout
        graph = self._context.graph
        own = str(session.info.zid())
        names = set(self._topics) | ({'/clock'} if self._clock_hz else set())
        while time.monotonic() < deadline and not self._stop.is_set():
            zids = {e.zid for e in graph.entities()
                    if e.kind == EntityKind.SUBSCRIPTION and e.name in names and e.zid != own}
            linked = {str(z) for z in session.info.peers_zid()}
            if zids <= linked:
                time.sleep(0.1)  # their subscriber declarations travel right behind the link
                return
            time.sleep(0.02)

    # -- playing ------------------------------------------------------------------------------
    def _play_once(self, senders: dict, clock: Any) -> None:
        first = self._summary.start + self._offset_ns if self._summary.message_count else 0
        start_wall = time.monotonic()
        next_clock = start_wall
        clock_period = 1.0 / self._clock_hz if self._clock_hz else None

        def publish_clock(now: float) -> None:
            publisher, clock_type = clock
            bag_ns = first + int((now - start_wall) * self._rate * 1e9)
            msg = clock_type()
            msg.clock.sec, msg.clock.nanosec = divmod(bag_ns, 1_000_000_000)
            publisher.publish(msg)

        for message in self._reader.messages(self._topics, start_time=first if self._offset_ns else None):
            send = senders.get(message.topic)
            if send is None:
                continue
            due = start_wall + (message.log_time - first) / 1e9 / self._rate
            while True:
                if self._stop.is_set():
                    return
                now = time.monotonic()
                if clock is not None and now >= next_clock:
                    publish_clock(now)
                    next_clock += clock_period
                    if next_clock < now:
                        next_clock = now + clock_period
                if now >= due:
                    break
                wake = due if clock is None else min(due, next_clock)
                self._stop.wait(min(0.1, max(0.0, wake - now)))
            send(message.data)
            self.published += 1
        if clock is not None and not self._stop.is_set():
            publish_clock(time.monotonic())
