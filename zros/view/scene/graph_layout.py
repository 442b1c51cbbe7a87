"""Layered drawing of a directed graph, left to right, as Graphviz's dot draws rqt_graph's picture.

Sugiyama's method (Sugiyama, Tagawa and Toda, "Methods for visual understanding of hierarchical
system structures", 1981; the steps as in Gansner et al., "A technique for drawing directed
graphs", 1993), in five plain steps:

1. cycles: the Eades-Lin-Smyth greedy order of the vertices; an edge against it is reversed for
   the ranking only (drawn right to left, as dot draws a back edge)
2. layers: longest path from the sources; a source is then pulled right, next to its first
   successor (a topic nothing publishes sits just left of its subscribers, not in column 0)
3. an edge longer than one layer becomes a chain of dummy vertices, one per layer it crosses
4. crossing reduction: barycentre sweeps left-to-right and right-to-left, keeping the order with
   the fewest crossings (counted pairwise, vectorised)
5. coordinates: a column per layer, as wide as its widest box; rows are pulled towards the mean
   row of their neighbours and kept apart by isotonic regression (pool adjacent violators)

Pure: vertices, edges and box widths in, boxes and edge routes out; zros.view.scene.graph_svg
draws them.
"""
from __future__ import annotations

from typing import Mapping, NamedTuple, Sequence

import numpy as np

__all__ = ['Box', 'GraphLayout', 'layered_layout']

SWEEPS = 12            # barycentre passes (each one way) in the crossing reduction
PLACEMENT_SWEEPS = 8   # neighbour-pulling passes (each one way) in the row placement
DUMMY_HEIGHT = 6.0     # [px] the room a long edge takes in a column it crosses


class Box(NamedTuple):
    """One vertex's box: top-left corner, size [px] and its layer (column)."""

    x: float
    y: float
    width: float
    height: float
    layer: int


class GraphLayout(NamedTuple):
    """Where everything goes.

    boxes: vertex -> Box. routes: edge (src, dst) -> the points [px] its line passes through,
    from the side of src's box to the side of dst's box (right to left for a reversed edge).
    width, height: the drawing's size [px], margins included.
    """

    boxes: dict[str, Box]
    routes: dict[tuple[str, str], list[tuple[float, float]]]
    width: float
    height: float


def layered_layout(vertices: Sequence[str], edges: Sequence[tuple[str, str]], widths: Mapping[str, float], *,
                   box_height: float = 30.0, column_gap: float = 60.0, row_gap: float = 14.0,
                   margin: float = 14.0) -> GraphLayout:
    """Lay `vertices` out in layers, left to right, every edge pointing right where cycles allow.

    Args:
        vertices: the vertex ids, in a stable order (it breaks ties).
        edges: (src, dst) pairs; pairs naming unknown vertices, self-loops and repeats are ignored.
        widths: each vertex's box width [px].
        box_height, column_gap, row_gap, margin: sizes [px].
    Returns:
        GraphLayout. Boxes never overlap; a kept edge's dst is in a layer right of its src's.
    """
    index = {v: i for i, v in enumerate(dict.fromkeys(vertices))}
    names = list(index)
    pairs = list(dict.fromkeys((index[s], index[d]) for s, d in edges if s in index and d in index and s != d))
    if not names:
        return GraphLayout({}, {}, 2 * margin, 2 * margin)
    forward = _acyclic(len(names), pairs)
    layer = _layers(len(names), forward)
    chains, layer_of = _split_long_edges(forward, layer)
    order = _reduce_crossings(chains, layer_of)
    size = [float(widths.get(n, 60.0)) for n in names] + [0.0] * (len(layer_of) - len(names))
    heights = np.array([box_height] * len(names) + [DUMMY_HEIGHT] * (len(layer_of) - len(names)))
    centres = _place_rows(order, chains, heights, row_gap)
    column_x, column_w = [], []
    x = margin
    for column in order:
        width = max((size[v] for v in column), default=0.0)
        column_x.append(x)
        column_w.append(width)
        x += width + column_gap
    top = min(centres[v] - heights[v] / 2 for column in order for v in column)
    shift = margin - top
    boxes = {}
    for v, name in enumerate(names):
        k = layer_of[v]
        boxes[name] = Box(column_x[k] + (column_w[k] - size[v]) / 2, centres[v] - box_height / 2 + shift,
                          size[v], box_height, k)
    routes = {}
    for (s, d), chain, pair in zip(forward, chains, pairs):
        reversed_edge = (s, d) != pair
        src, dst = (names[d], names[s]) if reversed_edge else (names[s], names[d])
        points = []
        for v in chain:
            k = layer_of[v]
            y = centres[v] + shift
            if v < len(names):
                box = boxes[names[v]]
                points.append((box.x, y) if v == chain[-1] else (box.x + box.width, y))
            else:
                points.extend([(column_x[k], y), (column_x[k] + column_w[k], y)])
        if reversed_edge:                 # from src's left side back to dst's right side
            points.reverse()
        routes[(src, dst)] = points
    height = max(b.y + b.height for b in boxes.values()) + margin
    return GraphLayout(boxes, routes, x - column_gap + margin, height)


def _acyclic(count: int, pairs: list[tuple[int, int]]) -> list[tuple[int, int]]:
    """The edges, those against the Eades-Lin-Smyth greedy order reversed (so the result has no cycle)."""
    outgoing: list[set[int]] = [set() for _ in range(count)]
    incoming: list[set[int]] = [set() for _ in range(count)]
    for s, d in pairs:
        outgoing[s].add(d)
        incoming[d].add(s)
    left, right = [], []
    alive = set(range(count))
    while alive:
        changed = True
        while changed:
            changed = False
            for v in sorted(alive):
                if not outgoing[v] & alive:           # a sink goes last
                    right.append(v)
                elif not incoming[v] & alive:         # a source goes first
                    left.append(v)
                else:
                    continue
                alive.discard(v)
                changed = True
        if alive:
            v = max(sorted(alive), key=lambda u: len(outgoing[u] & alive) - len(incoming[u] & alive))
            left.append(v)
            alive.discard(v)
    rank = {v: i for i, v in enumerate(left + right[::-1])}
    return [(s, d) if rank[s] < rank[d] else (d, s) for s, d in pairs]


def _layers(count: int, edges: list[tuple[int, int]]) -> list[int]:
    """Longest path from the sources, then each source moved right next to its nearest successor."""
    successors: list[list[int]] = [[] for _ in range(count)]
    indegree = [0] * count
    for s, d in edges:
        successors[s].append(d)
        indegree[d] += 1
    layer = [0] * count
    ready = [v for v in range(count) if indegree[v] == 0]
    sources = list(ready)
    while ready:
        v = ready.pop()
        for d in successors[v]:
            layer[d] = max(layer[d], layer[v] + 1)
            indegree[d] -= 1
            if indegree[d] == 0:
                ready.append(d)
    for v in sources:
        if successors[v]:
            layer[v] = min(layer[d] for d in successors[v]) - 1
    low = min(layer)
    return [k - low for k in layer]


def _split_long_edges(edges: list[tuple[int, int]], layer: list[int]) -> tuple[list[list[int]], list[int]]:
    """Each edge as a chain of vertices one layer apart (dummies numbered after the real vertices),
    and every vertex's layer."""
    layer_of = list(layer)
    chains = []
    for s, d in edges:
        chain = [s]
        for k in range(layer[s] + 1, layer[d]):
            layer_of.append(k)
            chain.append(len(layer_of) - 1)
        chain.append(d)
        chains.append(chain)
    return chains, layer_of


def _links(chains: list[list[int]], layer_of: list[int]) -> list[np.ndarray]:
    """For each pair of neighbouring layers k, k+1: the (left vertex, right vertex) links as an (E, 2) array."""
    depth = max(layer_of) + 1
    links: list[list[tuple[int, int]]] = [[] for _ in range(max(depth - 1, 0))]
    for chain in chains:
        for a, b in zip(chain, chain[1:]):
            links[layer_of[a]].append((a, b))
    return [np.array(pair, dtype=np.int64).reshape(-1, 2) for pair in links]


def _crossings(links: list[np.ndarray], position: np.ndarray) -> int:
    """Edge crossings between neighbouring layers: pairs of links whose ends are in opposite orders."""
    total = 0
    for pair in links:
        if len(pair) < 2:
            continue
        left, right = position[pair[:, 0]], position[pair[:, 1]]
        total += int(np.count_nonzero(np.sign(left[:, None] - left[None, :])
                                      * np.sign(right[:, None] - right[None, :]) < 0)) // 2
    return total


def _reduce_crossings(chains: list[list[int]], layer_of: list[int]) -> list[list[int]]:
    """Each layer's vertices top to bottom, ordered by barycentre sweeps (fewest crossings seen)."""
    depth = max(layer_of) + 1
    order = [[v for v in range(len(layer_of)) if layer_of[v] == k] for k in range(depth)]
    links = _links(chains, layer_of)
    position = np.zeros(len(layer_of))
    for column in order:
        position[column] = np.arange(len(column))
    best, best_count = [list(c) for c in order], _crossings(links, position)
    for sweep in range(SWEEPS):
        down = sweep % 2 == 0
        for k in (range(1, depth) if down else range(depth - 2, -1, -1)):
            pair = links[k - 1] if down else links[k]
            fixed, moving = (pair[:, 0], pair[:, 1]) if down else (pair[:, 1], pair[:, 0])
            total = np.bincount(moving, weights=position[fixed], minlength=len(layer_of))
            count = np.bincount(moving, minlength=len(layer_of))
            column = np.array(order[k])
            keys = np.where(count[column] > 0, total[column] / np.maximum(count[column], 1), position[column])
            column = column[np.argsort(keys, kind='stable')]
            order[k] = column.tolist()
            position[column] = np.arange(len(column))
        count_now = _crossings(links, position)
        if count_now < best_count:
            best, best_count = [list(c) for c in order], count_now
        if best_count == 0:
            break
    return best


def _place_rows(order: list[list[int]], chains: list[list[int]], heights: np.ndarray, gap: float) -> np.ndarray:
    """Each vertex's centre row [px]: pulled to its neighbours' mean, in order, never overlapping."""
    neighbours_left: list[list[int]] = [[] for _ in range(len(heights))]
    neighbours_right: list[list[int]] = [[] for _ in range(len(heights))]
    for chain in chains:
        for a, b in zip(chain, chain[1:]):
            neighbours_right[a].append(b)
            neighbours_left[b].append(a)
    centre = np.zeros(len(heights))
    for column in order:
        spacing = _spacing(heights[column], gap)
        centre[column] = spacing - spacing.mean()
    for sweep in range(PLACEMENT_SWEEPS):
        down = sweep % 2 == 0
        for column in (order[1:] if down else order[-2::-1]):
            near = neighbours_left if down else neighbours_right
            wanted = np.array([centre[near[v]].mean() if near[v] else centre[v] for v in column])
            spacing = _spacing(heights[column], gap)
            centre[column] = _isotonic(wanted - spacing) + spacing
    return centre


def _spacing(heights: np.ndarray, gap: float) -> np.ndarray:
    """Offsets of centres stacked with `gap` between boxes of these heights, the first at 0."""
    steps = (heights[:-1] + heights[1:]) / 2 + gap
    return np.concatenate([[0.0], np.cumsum(steps)])


def _isotonic(values: np.ndarray) -> np.ndarray:
    """The non-decreasing sequence closest to `values` in least squares (pool adjacent violators)."""
    blocks: list[list[float]] = []          # [sum, count]
    for value in values:
        blocks.append([float(value), 1.0])
        while len(blocks) > 1 and blocks[-2][0] / blocks[-2][1] > blocks[-1][0] / blocks[-1][1]:
            total, count = blocks.pop()
            blocks[-1][0] += total
            blocks[-1][1] += count
    return np.concatenate([np.full(int(count), total / count) for total, count in blocks]) if blocks else values
