"""The tabs of the view's side panel: rqt's tools in the same page as the scene.

A `Page` builds its widgets once, inside its tab, and is refreshed about twice a second from the
view's slow thread. The view ships Topics, Images, Graph (rqt_graph) and Console (rqt_console);
more pages (plot, topic monitor, service caller, parameters) plug in with
`SceneView.add_page(page)`:

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
from typing import TYPE_CHECKING, Any

from zros.view.scene.console import LEVELS, LogBuffer, to_html
from zros.view.scene.graph_svg import to_svg

if TYPE_CHECKING:
    from zros.view.scene.app import SceneView

__all__ = ['Page', 'TopicsPage', 'ImagesPage', 'GraphPage', 'ConsolePage', 'TopicRates']


class Page:
    """One tab of the side panel. `title` and `icon` (a viser.Icon name) label the tab."""

    title: str = ''
    icon: str | None = None

    def build(self, view: 'SceneView') -> None:
        """Add this page's widgets with `view.gui` (called once, inside the tab's container)."""

    def refresh(self, now: float) -> None:
        """Bring the widgets up to date (the view's slow thread, about twice a second)."""

    def close(self) -> None:
        """Release subscriptions; the widgets go with the server."""


class TopicRates:
    """Message rates of topics, from arrival times (the last `window` seconds).

    The view counts the messages its displays receive; topics without a display get a raw,
    best-effort subscription (no decoding, matching any publisher's QoS) that only counts.
    """

    def __init__(self, window: float = 5.0) -> None:
        self.window = window
        self._arrivals: dict[str, deque[float]] = {}
        self._lock = threading.Lock()

    def count(self, topic: str) -> None:
        now = time.monotonic()
        with self._lock:
            arrivals = self._arrivals.setdefault(topic, deque(maxlen=1000))
            arrivals.append(now)

    def rate(self, topic: str) -> float | None:
        """Messages per second over the window; None if fewer than two arrived in it."""
        now = time.monotonic()
        with self._lock:
            arrivals = [t for t in self._arrivals.get(topic, ()) if now - t <= self.window]
        if len(arrivals) < 2:
            return None
        span = arrivals[-1] - arrivals[0]
        return (len(arrivals) - 1) / span if span > 0 else None


class TopicsPage(Page):
    """Every topic of the graph with its type, publishers, subscribers and rate."""

    title, icon = 'Topics', 'list-details'

    def __init__(self) -> None:
        self.view: 'SceneView | None' = None
        self.table: Any = None
        self._counters: dict[str, Any] = {}

    def build(self, view: 'SceneView') -> None:
        self.view = view
        self.table = view.gui.add_html('<div style="color:#888;font-size:12px">reading the graph…</div>')

    def refresh(self, now: float) -> None:
        view = self.view
        if view is None:
            return
        topics = view.topic_types()
        shown = {name for name, _ in topics}
        for name in list(self._counters):
            if name not in shown:
                view.node.destroy_subscription(self._counters.pop(name))
        for name, types in topics:
            if name not in self._counters and not view.displays_on(name) and types:
                self._counters[name] = self._raw_counter(view, name, types[0])
        rows = []
        for name, types in topics:
            rate = view.rates.rate(name)
            pubs, subs = view.endpoint_counts(name)
            rate_text = f'{rate:.1f} Hz' if rate is not None else '—'
            rows.append(f'<tr style="border-top:1px solid #eee"><td style="padding:3px 6px 3px 0">'
                        f'<div style="font-weight:600">{_esc(name)}</div>'
                        f'<div style="color:#777;font-size:11px">{_esc(", ".join(types))}</div></td>'
                        f'<td style="padding:3px 6px;text-align:right;white-space:nowrap;color:#555">{pubs} / {subs}</td>'
                        f'<td style="padding:3px 0 3px 6px;text-align:right;white-space:nowrap">{rate_text}</td></tr>')
        self.table.content = (
            '<table style="font-size:12px;border-collapse:collapse;width:100%"><thead><tr style="color:#777;'
            'text-align:left;font-weight:normal"><th>Topic · type</th><th style="text-align:right;padding:0 6px">'
            'Pub / Sub</th><th style="text-align:right">Rate</th></tr></thead><tbody>' + ''.join(rows)
            + '</tbody></table>' if rows else '<div style="color:#888;font-size:12px">no topics in the graph</div>')

    @staticmethod
    def _raw_counter(view: 'SceneView', topic: str, type_name: str) -> Any:
        from zros.qos import qos_profile_sensor_data
        from zros.typesupport import get_message
        try:
            msg_class = get_message(type_name)
        except Exception:  # noqa: BLE001 - a type this machine does not have: no rate, no error
            return None
        return view.node.create_subscription(msg_class, topic, lambda _payload: view.rates.count(topic),
                                             qos_profile_sensor_data, raw=True)

    def close(self) -> None:
        if self.view is not None:
            for subscription in self._counters.values():
                if subscription is not None:
                    try:
                        self.view.node.destroy_subscription(subscription)
                    except Exception:  # noqa: BLE001 - the node may be gone
                        pass
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
    """rqt_graph's picture: nodes and the topics between them, redrawn when the graph changes."""

    title, icon = 'Graph', 'topology-star-3'

    def __init__(self) -> None:
        self.view: 'SceneView | None' = None
        self.picture: Any = None
        self.options: Any = None
        self._key: Any = None
        self.svg = ''

    def build(self, view: 'SceneView') -> None:
        self.view = view
        self.options = view.gui.add_checkbox('Hidden and debug too', False,
                                             hint='Show hidden nodes/topics, /rosout and /parameter_events')
        self.picture = view.gui.add_html('')

    def refresh(self, now: float) -> None:
        from zros.cli.graph import graph_content
        if self.view is None:
            return
        everything = bool(self.options.value)
        content = graph_content(self.view.graph_entities(), include_hidden=everything, include_debug=everything)
        key = (repr(content), everything)
        if key == self._key:
            return
        self._key = key
        self.svg = to_svg(content)
        self.picture.content = f'<div style="overflow:auto;max-height:75vh">{self.svg}</div>'


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
        if self.view is not None and self._subscription is not None:
            try:
                self.view.node.destroy_subscription(self._subscription)
            except Exception:  # noqa: BLE001 - the node may be gone
                pass


def _esc(text: str) -> str:
    import html
    return html.escape(text)
