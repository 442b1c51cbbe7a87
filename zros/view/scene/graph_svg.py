"""The node/topic graph (rqt_graph's picture) as SVG, laid out in Python: no Graphviz needed.

Layout is the usual layered drawing: each vertex gets a column by its longest path from a source
(cycles broken by depth-first search), vertices within a column are ordered by the mean row of
their neighbours (a few sweeps left and right), and edges are drawn as curves left to right.
Input is `zros.cli.graph.graph_content`'s dict: node names, topics with types, and edges between
'n:<node>' and 't:<topic>' ids.
"""
from __future__ import annotations

import html
from typing import Any

__all__ = ['layout', 'to_svg']

COLUMN_GAP, ROW_GAP, CHAR_W, BOX_H, PAD = 70, 18, 7.0, 30, 14


def _label(vertex: str) -> str:
    return vertex[2:]


def _width(vertex: str) -> float:
    return max(60.0, len(_label(vertex)) * CHAR_W + 2 * PAD)


def layout(content: dict[str, Any]) -> dict[str, tuple[float, float, float]]:
    """{vertex id: (x, y, width)} with x, y the box's top-left corner [px]."""
    vertices = ['n:' + n for n in content['nodes']] + ['t:' + t for t in content['topics']]
    outgoing: dict[str, list[str]] = {v: [] for v in vertices}
    incoming: dict[str, list[str]] = {v: [] for v in vertices}
    for src, dst in content['edges']:
        if src in outgoing and dst in outgoing:
            outgoing[src].append(dst)
            incoming[dst].append(src)
    # Break cycles: drop edges that close a cycle in a depth-first walk.
    state: dict[str, int] = {}
    kept: dict[str, list[str]] = {v: [] for v in vertices}

    def visit(start: str) -> None:
        stack = [(start, iter(outgoing[start]))]
        state[start] = 1
        while stack:
            vertex, children = stack[-1]
            for child in children:
                if state.get(child) == 1:
                    continue                      # back edge: leave it out of the ranking
                kept[vertex].append(child)
                if child not in state:
                    state[child] = 1
                    stack.append((child, iter(outgoing[child])))
                    break
            else:
                state[vertex] = 2
                stack.pop()
    for vertex in sorted(vertices, key=lambda v: (len(incoming[v]) > 0, v)):
        if vertex not in state:
            visit(vertex)
    rank = {v: 0 for v in vertices}
    order = _topological(vertices, kept)
    for vertex in order:
        for child in kept[vertex]:
            rank[child] = max(rank[child], rank[vertex] + 1)
    columns: dict[int, list[str]] = {}
    for vertex in vertices:
        columns.setdefault(rank[vertex], []).append(vertex)
    for column in columns.values():
        column.sort()
    for sweep in range(4):
        keys = sorted(columns) if sweep % 2 == 0 else sorted(columns, reverse=True)
        for key in keys:
            position = {v: i for col in columns.values() for i, v in enumerate(col)}
            neighbours = incoming if sweep % 2 == 0 else outgoing

            def barycentre(vertex: str) -> float:
                rows = [position[n] for n in neighbours[vertex] if n in position]
                return sum(rows) / len(rows) if rows else position[vertex]
            columns[key].sort(key=barycentre)
    placed: dict[str, tuple[float, float, float]] = {}
    x = float(PAD)
    for key in sorted(columns):
        width = max(_width(v) for v in columns[key])
        for row, vertex in enumerate(columns[key]):
            placed[vertex] = (x + (width - _width(vertex)) / 2, PAD + row * (BOX_H + ROW_GAP), _width(vertex))
        x += width + COLUMN_GAP
    return placed


def _topological(vertices: list[str], edges: dict[str, list[str]]) -> list[str]:
    indegree = {v: 0 for v in vertices}
    for children in edges.values():
        for child in children:
            indegree[child] += 1
    ready = sorted(v for v in vertices if indegree[v] == 0)
    out: list[str] = []
    while ready:
        vertex = ready.pop(0)
        out.append(vertex)
        for child in edges[vertex]:
            indegree[child] -= 1
            if indegree[child] == 0:
                ready.append(child)
    return out


def to_svg(content: dict[str, Any], *, dark: bool = False) -> str:
    """The graph as a standalone SVG document (nodes as ellipses, topics as boxes)."""
    placed = layout(content)
    if not placed:
        return ('<svg xmlns="http://www.w3.org/2000/svg" width="320" height="40">'
                '<text x="10" y="25" font-family="sans-serif" font-size="13" fill="#888">'
                'no nodes in the graph</text></svg>')
    width = max(x + w for x, _, w in placed.values()) + PAD
    height = max(y for _, y, _ in placed.values()) + BOX_H + PAD
    ink = '#ddd' if dark else '#333'
    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0f}" height="{height:.0f}" '
             f'viewBox="0 0 {width:.0f} {height:.0f}" font-family="sans-serif" font-size="12" '
             'style="max-width:100%;height:auto">',
             '<defs><marker id="zros-arrow" viewBox="0 0 10 10" refX="10" refY="5" markerWidth="7" '
             f'markerHeight="7" orient="auto"><path d="M0,0 L10,5 L0,10 z" fill="{ink}"/></marker></defs>']
    for src, dst in content['edges']:
        if src not in placed or dst not in placed:
            continue
        sx, sy, sw = placed[src]
        dx, dy, _ = placed[dst]
        x1, y1, x2, y2 = sx + sw, sy + BOX_H / 2, dx, dy + BOX_H / 2
        if x2 <= x1:                                   # a back edge: loop around below
            bend = BOX_H * 1.5
            path = f'M{x1:.1f},{y1:.1f} C{x1 + 60:.1f},{y1 + bend:.1f} {x2 - 60:.1f},{y2 + bend:.1f} {x2:.1f},{y2:.1f}'
        else:
            mid = (x1 + x2) / 2
            path = f'M{x1:.1f},{y1:.1f} C{mid:.1f},{y1:.1f} {mid:.1f},{y2:.1f} {x2:.1f},{y2:.1f}'
        parts.append(f'<path d="{path}" fill="none" stroke="{ink}" stroke-width="1.2" '
                     'marker-end="url(#zros-arrow)"/>')
    for vertex, (x, y, w) in placed.items():
        label = html.escape(_label(vertex))
        if vertex.startswith('n:'):
            shape = (f'<ellipse cx="{x + w / 2:.1f}" cy="{y + BOX_H / 2:.1f}" rx="{w / 2:.1f}" ry="{BOX_H / 2}" '
                     'fill="#dbe9ff" stroke="#3b6fd1" stroke-width="1.2"/>')
            title = 'node ' + label
        else:
            shape = (f'<rect x="{x:.1f}" y="{y:.1f}" width="{w:.1f}" height="{BOX_H}" rx="3" '
                     'fill="#fff4d6" stroke="#c78a00" stroke-width="1.2"/>')
            title = html.escape(', '.join(content['topics'].get(_label(vertex), [])))
        parts.append(f'<g><title>{title}</title>{shape}<text x="{x + w / 2:.1f}" y="{y + BOX_H / 2 + 4:.1f}" '
                     f'text-anchor="middle" fill="#111">{label}</text></g>')
    parts.append('</svg>')
    return ''.join(parts)
