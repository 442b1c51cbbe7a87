"""Drawings of the frame tree: Graphviz DOT text (view_frames' format) and a self-contained SVG
laid out here, for machines without Graphviz.

Both take `BufferCore.frames()`: per child frame its parent, authority, rate, sample count and
oldest/newest stamps.
"""
from __future__ import annotations

from html import escape
from typing import Any

__all__ = ['edge_label_lines', 'to_dot', 'to_svg']

_NODE_H = 36          # ellipse height [px]
_ROW = 160            # vertical distance between tree levels [px]
_SLOT = 250           # horizontal room per leaf [px]
_FONT = 13
_LABEL_FONT = 10


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


def to_svg(frames: dict[str, dict[str, Any]], recorded_seconds: float) -> str:
    """An SVG drawing of the tree, with view_frames' edge labels and legend."""
    margin_x, top = 40.0, 90.0
    if not frames:
        return ('<svg xmlns="http://www.w3.org/2000/svg" width="360" height="80">'
                '<text x="20" y="45" font-family="sans-serif" font-size="16">No tf data received</text></svg>\n')
    positions = _layout(frames)
    width = max(x for x, _ in positions.values()) + _SLOT + 2 * margin_x
    height = max(y for _, y in positions.values()) + top + _NODE_H + 40

    def at(frame: str) -> tuple[float, float]:
        x, y = positions[frame]
        return x + margin_x + _SLOT / 2.0, y + top

    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0f}" height="{height:.0f}" '
             f'viewBox="0 0 {width:.0f} {height:.0f}" font-family="sans-serif">',
             '<rect width="100%" height="100%" fill="white"/>',
             '<defs><marker id="arrow" viewBox="0 0 10 10" refX="10" refY="5" markerWidth="8" markerHeight="8" '
             'orient="auto"><path d="M0,0 L10,5 L0,10 z" fill="black"/></marker></defs>',
             f'<rect x="10" y="10" width="300" height="50" fill="none" stroke="black" stroke-width="2"/>',
             f'<text x="160" y="30" text-anchor="middle" font-size="{_FONT}">view_frames Result</text>',
             f'<text x="160" y="50" text-anchor="middle" font-size="{_LABEL_FONT}">Recorded at time: '
             f'{recorded_seconds}</text>']
    for child, info in frames.items():
        (px, py), (cx, cy) = at(info['parent']), at(child)
        # elbow edges: down from the parent, across, down into the child; the label stands
        # beside the last drop, where no other edge runs
        bar = py + _NODE_H / 2 + 18
        parts.append(f'<path d="M{px:.1f},{py + _NODE_H / 2:.1f} V{bar:.1f} H{cx:.1f} V{cy - _NODE_H / 2:.1f}" '
                     'fill="none" stroke="black" marker-end="url(#arrow)"/>')
        lines = edge_label_lines(info)
        ly = cy - _NODE_H / 2 - 8 - (len(lines) - 1) * (_LABEL_FONT + 2)
        for i, line in enumerate(lines):
            parts.append(f'<text x="{cx + 6:.1f}" y="{ly + i * (_LABEL_FONT + 2):.1f}" '
                         f'font-size="{_LABEL_FONT}">{escape(line)}</text>')
    for frame in positions:
        x, y = at(frame)
        rx = max(40.0, 4.2 * len(frame) + 16)
        parts.append(f'<ellipse cx="{x:.1f}" cy="{y:.1f}" rx="{rx:.1f}" ry="{_NODE_H / 2}" fill="white" '
                     'stroke="black"/>')
        parts.append(f'<text x="{x:.1f}" y="{y + _FONT / 3:.1f}" text-anchor="middle" font-size="{_FONT}">'
                     f'{escape(frame)}</text>')
    parts.append('</svg>')
    return '\n'.join(parts) + '\n'
