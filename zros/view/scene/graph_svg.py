"""The node/topic graph (rqt_graph's picture) as SVG, laid out in Python: no Graphviz needed.

Input is `zros.graph_content.graph_content`'s dict (node names, topics with types, edges between
'n:<node>' and 't:<topic>' ids), usually after zros.view.scene.graph_hides; the layout is
zros.view.scene.graph_layout's layered one, left to right: publishers, topics, subscribers.
Nodes are ellipses, topics boxes, and edges curves through the layout's route points.
"""
from __future__ import annotations

import html
from typing import Any

from zros.view.scene.graph_layout import GraphLayout, layered_layout

__all__ = ['layout', 'to_svg']

CHAR_W, BOX_H, PAD = 7.0, 30, 14        # [px] a character of the 12 px font, a box's height, a label's margin


def _label(vertex: str) -> str:
    return vertex[2:]


def _width(vertex: str) -> float:
    return max(60.0, len(_label(vertex)) * CHAR_W + 2 * PAD)


def layout(content: dict[str, Any]) -> GraphLayout:
    """The layered layout of `content`'s nodes and topics (boxes sized for their labels)."""
    vertices = ['n:' + n for n in content['nodes']] + ['t:' + t for t in content['topics']]
    return layered_layout(vertices, content['edges'], {v: _width(v) for v in vertices}, box_height=BOX_H)


def _path(points: list[tuple[float, float]]) -> str:
    """SVG path data through `points`: a curve leaving and entering each point horizontally."""
    (x0, y0), rest = points[0], points[1:]
    parts = [f'M{x0:.1f},{y0:.1f}']
    for x1, y1 in rest:
        if y1 == y0:
            parts.append(f'L{x1:.1f},{y1:.1f}')
        else:
            mid = (x0 + x1) / 2
            parts.append(f'C{mid:.1f},{y0:.1f} {mid:.1f},{y1:.1f} {x1:.1f},{y1:.1f}')
        x0, y0 = x1, y1
    return ' '.join(parts)


def to_svg(content: dict[str, Any], *, dark: bool = False, fit: bool = False) -> str:
    """The graph as a standalone SVG document: at its natural size (12 px labels, to scroll), or
    with `fit` as wide as its container (a wide graph's labels then shrink)."""
    placed = layout(content)
    if not placed.boxes:
        return ('<svg xmlns="http://www.w3.org/2000/svg" width="320" height="40">'
                '<text x="10" y="25" font-family="sans-serif" font-size="13" fill="#888">'
                'no nodes in the graph</text></svg>')
    width, height = placed.width, placed.height
    ink = '#ddd' if dark else '#444'
    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0f}" height="{height:.0f}" '
             f'viewBox="0 0 {width:.0f} {height:.0f}" font-family="sans-serif" font-size="12"'
             + (' style="width:100%;height:auto">' if fit else '>'),
             '<defs><marker id="zros-arrow" viewBox="0 0 10 10" refX="10" refY="5" markerWidth="7" '
             f'markerHeight="7" orient="auto"><path d="M0,0 L10,5 L0,10 z" fill="{ink}"/></marker></defs>']
    for (src, dst), points in placed.routes.items():
        parts.append(f'<path data-edge="{html.escape(src)} {html.escape(dst)}" d="{_path(points)}" fill="none" '
                     f'stroke="{ink}" stroke-width="1.2" marker-end="url(#zros-arrow)"/>')
    for vertex, box in placed.boxes.items():
        x, y, w = box.x, box.y, box.width
        label = html.escape(_label(vertex))
        if vertex.startswith('n:'):
            shape = (f'<ellipse cx="{x + w / 2:.1f}" cy="{y + BOX_H / 2:.1f}" rx="{w / 2:.1f}" ry="{BOX_H / 2}" '
                     'fill="#dbe9ff" stroke="#3b6fd1" stroke-width="1.2"/>')
            title = 'node ' + label
        else:
            shape = (f'<rect x="{x:.1f}" y="{y:.1f}" width="{w:.1f}" height="{BOX_H}" rx="3" '
                     'fill="#fff4d6" stroke="#c78a00" stroke-width="1.2"/>')
            title = html.escape(', '.join(content['topics'].get(_label(vertex), [])))
        parts.append(f'<g data-vertex="{html.escape(vertex)}"><title>{title}</title>{shape}'
                     f'<text x="{x + w / 2:.1f}" y="{y + BOX_H / 2 + 4:.1f}" text-anchor="middle" '
                     f'fill="#111">{label}</text></g>')
    parts.append('</svg>')
    return ''.join(parts)
