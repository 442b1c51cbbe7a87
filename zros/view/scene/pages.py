"""The tabs of the view's side panel: rqt's tools in the same page as the scene.

A `Page` builds its widgets once, inside its tab, and is refreshed about twice a second from the
view's slow thread. The view ships Topics (rqt's topic monitor), Images, Graph (rqt_graph) and Console
(rqt_console) from here, and Plot, Services and Parameters from zros.view.scene.rqt_pages;
more pages plug in with `SceneView.add_page(page)`:

    class PlotPage(Page):
        title, icon = 'Plot', viser.Icon.CHART_LINE
        def build(self, view):            # inside the tab: add widgets with view.gui
            self.chart = view.gui.add_uplot(...)
        def refresh(self, now):           # slow thread, ~2 Hz, only while the view runs
            ...
"""
from __future__ import annotations

import threading
import time
from collections import deque
from typing import TYPE_CHECKING, Any, Callable, Iterable

from zros.view.scene.console import LEVELS, LogBuffer, to_html
from zros.view.scene.graph_hides import Hides, apply_hides
from zros.view.scene.graph_svg import to_svg

if TYPE_CHECKING:
    from zros.view.scene.app import SceneView

__all__ = ['Page', 'TopicsPage', 'ImagesPage', 'GraphPage', 'ConsolePage', 'TopicStats', 'boxed', 'release']


class Page:
    """One tab of the side panel. `title` and `icon` (a viser.Icon name) label the tab."""

    title: str = ''
    icon: str | None = None
    tab: Any = None          # the page's tab (set by add_page): `with page.tab:` adds widgets to it later

    def build(self, view: 'SceneView') -> None:
        """Add this page's widgets with `view.gui` (called once, inside the tab's container)."""

    def refresh(self, now: float) -> None:
        """Bring the widgets up to date (the view's slow thread, about twice a second)."""

    def close(self) -> None:
        """Release subscriptions; the widgets go with the server."""


class TopicStats:
    """Rate and bandwidth of topics, from arrival times and sizes (the last `window` seconds)."""

    def __init__(self, window: float = 5.0) -> None:
        self.window = window
        self._arrivals: dict[str, deque[tuple[float, int]]] = {}
        self._lock = threading.Lock()

    def count(self, topic: str, size: int = 0) -> None:
        now = time.monotonic()
        with self._lock:
            arrivals = self._arrivals.setdefault(topic, deque(maxlen=1000))
            arrivals.append((now, size))

    def _recent(self, topic: str) -> list[tuple[float, int]]:
        now = time.monotonic()
        with self._lock:
            return [a for a in self._arrivals.get(topic, ()) if now - a[0] <= self.window]

    def rate(self, topic: str) -> float | None:
        """Messages per second over the window; None if fewer than two arrived in it."""
        arrivals = self._recent(topic)
        if len(arrivals) < 2:
            return None
        span = arrivals[-1][0] - arrivals[0][0]
        return (len(arrivals) - 1) / span if span > 0 else None

    def bandwidth(self, topic: str) -> float | None:
        """Bytes per second over the window (as `zros topic bw`); None like `rate`."""
        arrivals = self._recent(topic)
        rate = self.rate(topic)
        if rate is None:
            return None
        return rate * sum(size for _, size in arrivals) / len(arrivals)


class TopicsPage(Page):
    """rqt's topic monitor: every topic with its type, publishers/subscribers, rate and
    bandwidth, and the last message of the one picked, as a tree, updated live.

    Each topic gets a raw, best-effort subscription (no decoding, matching any publisher's QoS)
    that counts messages and bytes; only the picked topic's newest payload is decoded, at the
    page's refresh rate, so a busy topic costs the view no decoding.
    """

    title, icon = 'Topics', 'list-details'
    NONE = '(none)'

    def __init__(self) -> None:
        self.view: 'SceneView | None' = None
        self.table: Any = None
        self.picked: Any = None
        self.tree: Any = None
        self._counters: dict[str, Any] = {}
        self._latest: dict[str, Any] = {}       # picked topic -> newest payload
        self._shown_payload: Any = None

    def build(self, view: 'SceneView') -> None:
        self.view = view
        self.table = view.gui.add_html('<div style="color:#888;font-size:12px">reading the graph…</div>')
        self.picked = view.gui.add_dropdown('Message of', [self.NONE], initial_value=self.NONE,
                                            hint='Show the last message of this topic as a tree')
        self.tree = view.gui.add_html('')

    def refresh(self, now: float) -> None:
        view = self.view
        if view is None:
            return
        topics = view.topic_types()
        shown = {name for name, _ in topics}
        for name in list(self._counters):
            if name not in shown:
                release(view.node.destroy_subscription, [self._counters.pop(name)])
        for name, types in topics:
            if name not in self._counters and types:
                self._counters[name] = self._raw_counter(view, name, types[0])
        options = [self.NONE] + [name for name, _ in topics]
        if tuple(options) != tuple(self.picked.options):
            self.picked.options = options
        rows = []
        for name, types in topics:
            rate, bandwidth = view.stats.rate(name), view.stats.bandwidth(name)
            pubs, subs = view.endpoint_counts(name)
            rate_text = f'{rate:.1f} Hz' if rate is not None else '—'
            bw_text = _bytes_per_second(bandwidth) if bandwidth is not None else ''
            rows.append(f'<tr style="border-top:1px solid #eee"><td style="padding:3px 6px 3px 0">'
                        f'<div style="font-weight:600">{_esc(name)}</div>'
                        f'<div style="color:#777;font-size:11px">{_esc(", ".join(types))}</div></td>'
                        f'<td style="padding:3px 6px;text-align:right;white-space:nowrap;color:#555">{pubs} / {subs}</td>'
                        f'<td style="padding:3px 0 3px 6px;text-align:right;white-space:nowrap">{rate_text}'
                        f'<div style="color:#777;font-size:11px">{bw_text}</div></td></tr>')
        self.table.content = boxed(
            '<table style="font-size:12px;border-collapse:collapse;width:100%"><thead><tr style="color:#777;'
            'text-align:left;font-weight:normal"><th>Topic · type</th><th style="text-align:right;padding:0 6px">'
            'Pub / Sub</th><th style="text-align:right">Rate · bw</th></tr></thead><tbody>' + ''.join(rows)
            + '</tbody></table>' if rows else '<div style="color:#888;font-size:12px">no topics in the graph</div>')
        self._show_picked(dict(topics))

    def _show_picked(self, types: dict[str, list[str]]) -> None:
        from zros.convert import message_to_ordereddict
        from zros.message import deserialize
        from zros.typesupport import get_message
        from zros.view.scene.fields import message_tree_html
        topic = self.picked.value
        payload = self._latest.get(topic)
        if topic == self.NONE:
            content = ''
        elif payload is None:
            content = f'<div style="color:#888">no message on {_esc(topic)} yet</div>'
        elif payload is self._shown_payload:
            return
        else:
            try:
                msg = deserialize(payload, get_message(types[topic][0]))
                content = message_tree_html(message_to_ordereddict(msg, truncate_length=64))
            except Exception as exc:  # noqa: BLE001 - a type this machine lacks, a foreign payload
                content = f'<div style="color:#dc2626">cannot decode {_esc(topic)}: {_esc(str(exc))}</div>'
        self._shown_payload = payload
        self.tree.content = boxed(f'<div data-message-tree="{_esc(topic)}" style="font-size:12px;'
                                  f'font-family:monospace;max-height:45vh;overflow:auto">{content}</div>')

    def _raw_counter(self, view: 'SceneView', topic: str, type_name: str) -> Any:
        from zros.qos import qos_profile_sensor_data
        from zros.typesupport import get_message
        try:
            msg_class = get_message(type_name)
        except Exception:  # noqa: BLE001 - a type this machine does not have: no rate, no error
            return None

        def received(payload: Any) -> None:
            view.stats.count(topic, len(payload))
            if self.picked.value == topic:
                self._latest[topic] = bytes(payload)
        return view.node.create_subscription(msg_class, topic, received, qos_profile_sensor_data, raw=True)

    def close(self) -> None:
        if self.view is not None:
            release(self.view.node.destroy_subscription, self._counters.values())
        self._counters.clear()


class ImagesPage(Page):
    """Where Image displays draw; links the full-size image page and `zros image save`."""

    title, icon = 'Images', 'photo'

    def __init__(self, image_page_url: str | None = None) -> None:
        self.image_page_url = image_page_url
        self.container: Any = None
        self.note: Any = None

    def build(self, view: 'SceneView') -> None:
        link = (f'Full-size, 1:1 frames: <a href="{_esc(self.image_page_url)}" target="_blank">image page</a>. '
                if self.image_page_url else '')
        self.note = view.gui.add_html(
            f'<div style="font-size:12px;color:#555">{link}One frame as PNG: '
            '<code>zros image save TOPIC out.png</code></div>')

    def refresh(self, now: float) -> None:
        pass


class GraphPage(Page):
    """rqt_graph's picture: nodes and the topics between them, left to right, redrawn when the
    graph changes; rqt_graph's "Hide" checkboxes (zros.view.scene.graph_hides), all on at first."""

    title, icon = 'Graph', 'topology-star-3'
    #: Hides field -> (checkbox label, hint), in rqt_graph's order.
    HIDES = {'dead_sinks': ('Dead sinks', 'Hide topics nothing subscribes to'),
             'leaf_topics': ('Leaf topics', 'Hide topics with one connection only'),
             'debug': ('Debug', 'Hide debugging nodes and topics (/rosout, viewers, hidden names)'),
             'tf': ('tf', 'Hide /tf and /tf_static'),
             'params': ('Params', 'Hide /parameter_events')}

    def __init__(self) -> None:
        self.view: 'SceneView | None' = None
        self.picture: Any = None
        self.hide_boxes: dict[str, Any] = {}
        self.fit: Any = None
        self._key: Any = None
        self.svg = ''

    def build(self, view: 'SceneView') -> None:
        self.view = view
        with view.gui.add_folder('Hide'):
            for field, (label, hint) in self.HIDES.items():
                self.hide_boxes[field] = view.gui.add_checkbox(label, True, hint=hint)
        self.fit = view.gui.add_checkbox('Fit width', False, hint="Shrink the picture to the panel's width "
                                         "(rqt_graph's Fit in View); otherwise it scrolls at full size")
        self.picture = view.gui.add_html('')

    def hides(self) -> Hides:
        """The hides the checkboxes ask for."""
        return Hides(**{field: bool(box.value) for field, box in self.hide_boxes.items()})

    def refresh(self, now: float) -> None:
        from zros.graph_content import graph_content
        if self.view is None:
            return
        hides = self.hides()
        content = apply_hides(graph_content(self.view.graph_entities(), include_hidden=True, include_debug=True),
                              hides)
        fit = bool(self.fit.value)
        key = (repr(content), hides, fit)
        if key == self._key:
            return
        self._key = key
        self.svg = to_svg(content, fit=fit)
        self.picture.content = f'<div data-graph="1" style="overflow:auto;max-height:80vh">{self.svg}</div>'


class ConsolePage(Page):
    """rqt_console: /rosout with a minimum level, a node filter and a text search."""

    title, icon = 'Console', 'terminal-2'

    def __init__(self) -> None:
        self.view: 'SceneView | None' = None
        self.buffer = LogBuffer()
        self._subscription: Any = None
        self._shown: Any = None
        self.level = self.node = self.search = self.table = None

    def build(self, view: 'SceneView') -> None:
        from interfaces.rcl_interfaces.msg import Log
        from zros.qos import QoSProfile
        self.view = view
        self._subscription = view.node.create_subscription(Log, '/rosout', self.buffer.add, QoSProfile(depth=1000))
        self.level = view.gui.add_dropdown('Level ≥', list(LEVELS), initial_value='DEBUG')
        self.node = view.gui.add_dropdown('Node', ['(all)'], initial_value='(all)')
        self.search = view.gui.add_text('Search', '')
        self.table = view.gui.add_html(to_html([], total=0))

    def refresh(self, now: float) -> None:
        if self.table is None:
            return
        nodes = ['(all)'] + sorted(self.buffer.nodes)
        if tuple(nodes) != tuple(self.node.options):
            self.node.options = nodes
        node = '' if self.node.value == '(all)' else self.node.value
        key = (self.buffer.seq, self.level.value, node, self.search.value)
        if key == self._shown:
            return
        self._shown = key
        records = self.buffer.select(min_level=LEVELS[self.level.value], node=node, text=self.search.value)
        self.table.content = to_html(records, total=self.buffer.seq)

    def close(self) -> None:
        if self.view is not None:
            release(self.view.node.destroy_subscription, [self._subscription])


def release(destroy: Callable[[Any], Any], endpoints: Iterable[Any]) -> None:
    """Destroy a page's subscriptions or clients with `destroy`, skipping None and a node
    that is already gone (the view closes after its node at shutdown)."""
    for endpoint in endpoints:
        if endpoint is None:
            continue
        try:
            destroy(endpoint)
        except Exception:  # noqa: BLE001 - the node may be gone
            pass


def boxed(content: str) -> str:
    """HTML inset like viser's own widgets (an html widget otherwise touches the panel's edges)."""
    return f'<div style="padding:0 12px 0 10px">{content}</div>'


def _bytes_per_second(value: float) -> str:
    for unit, size in (('MB/s', 1e6), ('KB/s', 1e3)):
        if value >= size:
            return f'{value / size:.1f} {unit}'
    return f'{value:.0f} B/s'


def _esc(text: str) -> str:
    import html
    return html.escape(text)
