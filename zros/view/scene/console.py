"""/rosout as rqt_console shows it: the last log lines of every node, filtered by level, node and text.

`LogBuffer` keeps plain records (no message objects), so filtering and rendering never touch
the node; `to_html` renders the newest matching lines as a table for the page.
"""
from __future__ import annotations

import html
import threading
from collections import deque
from typing import Any, NamedTuple

__all__ = ['LogRecord', 'LogBuffer', 'LEVELS', 'level_name', 'to_html']

LEVELS = {'DEBUG': 10, 'INFO': 20, 'WARN': 30, 'ERROR': 40, 'FATAL': 50}
_COLORS = {10: '#6b7280', 20: '#1f2937', 30: '#b45309', 40: '#dc2626', 50: '#7f1d1d'}


class LogRecord(NamedTuple):
    seq: int
    stamp: float        # [s] since the epoch
    level: int
    node: str           # the logger name (the node's name, dotted for child loggers)
    text: str
    where: str          # file:line (function)


def level_name(level: int) -> str:
    for name, value in sorted(LEVELS.items(), key=lambda item: -item[1]):
        if level >= value:
            return name
    return 'DEBUG'


class LogBuffer:
    """The last `capacity` records; `add` is called by the node's executor, the rest by the page."""

    def __init__(self, capacity: int = 5000) -> None:
        self._records: deque[LogRecord] = deque(maxlen=capacity)
        self._lock = threading.Lock()
        self._seq = 0
        self.nodes: set[str] = set()

    def add(self, msg: Any) -> None:
        """Store one rcl_interfaces/msg/Log."""
        with self._lock:
            self._seq += 1
            where = f'{msg.file}:{msg.line} ({msg.function})' if msg.file else ''
            record = LogRecord(self._seq, msg.stamp.sec + msg.stamp.nanosec * 1e-9, int(msg.level), str(msg.name),
                               str(msg.msg), where)
            self._records.append(record)
            self.nodes.add(record.node)

    @property
    def seq(self) -> int:
        """Grows with every record: the page re-renders only when it changed."""
        return self._seq

    def select(self, *, min_level: int = 0, node: str = '', text: str = '', limit: int = 200) -> list[LogRecord]:
        """The newest `limit` records at `min_level` or above, from `node` (exact, '' = all), whose
        message contains `text` (case-insensitive), oldest first."""
        needle = text.lower()
        with self._lock:
            records = list(self._records)
        out = [r for r in reversed(records)
               if r.level >= min_level and (not node or r.node == node) and (not needle or needle in r.text.lower())]
        return out[:limit][::-1]


def to_html(records: list[LogRecord], *, total: int) -> str:
    """A compact table of records, newest last, with the level coloured."""
    import time
    if not records:
        return (f'<div style="color:#888;font-size:12px;padding:6px">no log lines match '
                f'({total} received)</div>')
    rows = []
    for r in records:
        color = _COLORS.get(r.level - r.level % 10, '#1f2937')
        clock = time.strftime('%H:%M:%S', time.localtime(r.stamp)) + f'.{int(r.stamp % 1 * 1000):03d}'
        rows.append(f'<tr title="{html.escape(r.where)}"><td style="color:#6b7280;white-space:nowrap">{clock}</td>'
                    f'<td style="color:{color};font-weight:600">{level_name(r.level)}</td>'
                    f'<td style="white-space:nowrap">{html.escape(r.node)}</td>'
                    f'<td style="color:{color}">{html.escape(r.text)}</td></tr>')
    return ('<table style="font-size:11.5px;font-family:ui-monospace,monospace;border-collapse:collapse;'
            'width:100%"><tbody>' + ''.join(rows) + '</tbody></table>'
            f'<div style="color:#888;font-size:11px;padding-top:4px">{len(records)} shown of {total} received</div>')
