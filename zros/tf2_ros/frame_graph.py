"""Drawings of the frame tree: Graphviz DOT text and a PDF, the two files ROS's view_frames
writes; the PDF is laid out here, so that no machine needs Graphviz.

Both take `BufferCore.frames()`: per child frame its parent, authority, rate, sample count and
oldest/newest stamps.
"""
from __future__ import annotations

from typing import Any

__all__ = ['edge_label_lines', 'to_dot', 'to_pdf']

_NODE_H = 36          # ellipse height [pt]
_ROW = 160            # vertical distance between tree levels [pt]
_SLOT = 250           # horizontal room per leaf [pt]
_FONT = 13            # frame names [pt]
_LABEL_FONT = 10      # edge labels and the legend's time [pt]


def edge_label_lines(info: dict[str, Any]) -> list[str]:
    """The text view_frames writes on the edge into a frame."""
    return [f"Broadcaster: {info['authority'] or 'no recorded authority'}",
            f"Average rate: {info['rate']:.3f}",
            f"Buffer length: {(info['newest'] - info['oldest']) / 1e9:.3f}",
            f"Most recent transform: {round(info['newest'] / 1e9, 6)}",
            f"Oldest transform: {round(info['oldest'] / 1e9, 6)}"]


def _roots(frames: dict[str, dict[str, Any]]) -> list[str]:
    return sorted({info['parent'] for info in frames.values()} - set(frames))


def to_dot(frames: dict[str, dict[str, Any]], recorded_seconds: float) -> str:
    """view_frames' DOT graph (parent -> child edges labelled with the frame's statistics)."""
    if not frames:
        return 'digraph G { "No tf data received" }\n'
    lines = ['digraph G {']
    for child, info in frames.items():
        label = '\\n'.join(edge_label_lines(info))
        lines.append(f'"{info["parent"]}" -> "{child}"[label=" {label}\\n"];')
    lines.append('edge [style=invis];')
    lines.append(' subgraph cluster_legend { style=bold; color=black; label ="view_frames Result";')
    lines.append(f'"Recorded at time: {recorded_seconds}"[ shape=plaintext ] ;')
    lines.append('}->"' + _roots(frames)[0] + '";')
    lines.append('}')
    return '\n'.join(lines) + '\n'


def _layout(frames: dict[str, dict[str, Any]]) -> dict[str, tuple[float, float]]:
    """Tidy tree: leaves take consecutive slots, a parent sits centred over its children."""
    children: dict[str, list[str]] = {}
    for child, info in frames.items():
        children.setdefault(info['parent'], []).append(child)
    positions: dict[str, tuple[float, float]] = {}
    next_slot = [0]

    def place(frame: str, depth: int, seen: set[str]) -> float:
        kids = [k for k in sorted(children.get(frame, [])) if k not in seen]
        if kids:
            xs = [place(k, depth + 1, seen | {frame}) for k in kids]
            x = (xs[0] + xs[-1]) / 2.0
        else:
            x = next_slot[0] * _SLOT
            next_slot[0] += 1
        positions[frame] = (x, depth * _ROW)
        return x
    for root in _roots(frames):
        place(root, 0, set())
    return positions


def to_pdf(frames: dict[str, dict[str, Any]], recorded_seconds: float) -> bytes:
    """A one-page PDF of the tree, with view_frames' edge labels and legend: what ROS's
    view_frames renders through Graphviz, laid out here so that no machine needs Graphviz."""
    from zros.pdf import PdfPage
    if not frames:
        page = PdfPage(360, 80)
        page.text(20, 45, 'No tf data received', 16)
        return page.to_bytes()
    margin_x, top = 40.0, 90.0
    positions = _layout(frames)
    page = PdfPage(max(x for x, _ in positions.values()) + _SLOT + 2 * margin_x,
                   max(y for _, y in positions.values()) + top + _NODE_H + 40)

    def at(frame: str) -> tuple[float, float]:
        x, y = positions[frame]
        return x + margin_x + _SLOT / 2.0, y + top

    page.rect(10, 10, 300, 50, line_width=2.0)
    page.text(160, 30, 'view_frames Result', _FONT, anchor='middle')
    page.text(160, 50, f'Recorded at time: {recorded_seconds}', _LABEL_FONT, anchor='middle')
    for child, info in frames.items():
        (px, py), (cx, cy) = at(info['parent']), at(child)
        # elbow edges: down from the parent, across, down into the child; the label stands
        # beside the last drop, where no other edge runs
        bar = py + _NODE_H / 2 + 18
        page.polyline([(px, py + _NODE_H / 2), (px, bar), (cx, bar), (cx, cy - _NODE_H / 2)], arrow=True)
        lines = edge_label_lines(info)
        ly = cy - _NODE_H / 2 - 8 - (len(lines) - 1) * (_LABEL_FONT + 2)
        for i, line in enumerate(lines):
            page.text(cx + 6, ly + i * (_LABEL_FONT + 2), line, _LABEL_FONT)
    for frame in positions:   # last, so that the ellipses cover the edges' ends
        x, y = at(frame)
        page.ellipse(x, y, max(40.0, 4.2 * len(frame) + 16), _NODE_H / 2)
        page.text(x, y + _FONT / 3, frame, _FONT, anchor='middle')
    return page.to_bytes()
