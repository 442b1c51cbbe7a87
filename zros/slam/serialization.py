"""A saved pose graph on disk: slam_toolbox's two files, in zros's own format.

slam_toolbox's `serialize_map` writes FILE.posegraph (the graph) and FILE.data (the scans), and
`deserialize_map`, the `map_file_name` parameter and merge_maps_kinematic's `add_submap` read
them back. zros writes the same two files, but not Karto's boost archives: each is a numpy
`.npz` (zip of `.npy` arrays, read without pickle), so a graph is readable from any Python:

FILE.posegraph:
    format            'zros-posegraph-2'
    parameters        JSON text: the SlamParameters it was made with
    poses  (N, 3)     optimised keyframe poses (x, y, yaw) in the map frame [m, rad]
    odom   (N, 3)     the odometry pose of each keyframe when it was taken
    travel (N,)       [m] travelled before each keyframe (loop closure bookkeeping)
    edge_nodes (E, 2), edge_measurements (E, 3), edge_information (E, 3, 3), edge_robust (E,)
FILE.data:
    format            'zros-posegraph-data-2'
    origins (N, 2)    each scan's sensor position in the base frame [m]
    hit_counts (N,), hits (sum, 2)        returns of all scans, concatenated, base frame [m]
    miss_counts (N,), misses (sum, 2)     ends of free rays of beams with no return [m]

A version-1 file (everything in FILE.posegraph, no FILE.data) is read too.
"""
from __future__ import annotations

import io
import json
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from zros.slam.pose_graph import Edge
from zros.slam.scan import ScanPoints

__all__ = ['SerializedGraph', 'PoseGraphFileError', 'write_pose_graph', 'read_pose_graph', 'pose_graph_files']

GRAPH_FORMAT = 'zros-posegraph-2'
DATA_FORMAT = 'zros-posegraph-data-2'
_OLD_FORMAT = 'zros-posegraph-1'


class PoseGraphFileError(ValueError):
    """A serialized pose graph that cannot be read or written (the text names the file)."""


class SerializedGraph(NamedTuple):
    """What a saved graph holds: keyframe poses, odometry, travel, scans and edges."""
    poses: np.ndarray
    odom: np.ndarray
    travel: np.ndarray
    scans: list[ScanPoints]
    edges: list[Edge]
    parameters: dict[str, Any]


def pose_graph_files(path: str | Path) -> tuple[Path, Path]:
    """FILE.posegraph and FILE.data for `path` given with or without the '.posegraph' suffix
    (slam_toolbox's requests name the file without it)."""
    base = str(Path(path).expanduser())
    if base.endswith('.posegraph'):
        base = base[:-len('.posegraph')]
    return Path(base + '.posegraph'), Path(base + '.data')


def write_pose_graph(path: str | Path, graph: SerializedGraph) -> tuple[Path, Path]:
    """Write FILE.posegraph and FILE.data; returns both paths."""
    graph_path, data_path = pose_graph_files(path)
    hits = [s.hits for s in graph.scans]
    misses = [s.misses for s in graph.scans]
    edges = graph.edges
    _write(graph_path, {
        'format': np.array(GRAPH_FORMAT), 'parameters': np.array(json.dumps(graph.parameters)),
        'poses': np.asarray(graph.poses).reshape(-1, 3), 'odom': np.asarray(graph.odom).reshape(-1, 3),
        'travel': np.asarray(graph.travel, dtype=np.float64),
        'edge_nodes': np.array([(e.i, e.j) for e in edges], dtype=np.int64).reshape(-1, 2),
        'edge_measurements': np.array([e.measurement for e in edges]).reshape(-1, 3),
        'edge_information': np.array([e.information for e in edges]).reshape(-1, 3, 3),
        'edge_robust': np.array([e.robust for e in edges], dtype=bool),
    })
    _write(data_path, {
        'format': np.array(DATA_FORMAT),
        'origins': np.array([s.origin for s in graph.scans]).reshape(-1, 2),
        'hit_counts': np.array([len(h) for h in hits], dtype=np.int64),
        'hits': np.vstack(hits) if hits else np.zeros((0, 2), np.float32),
        'miss_counts': np.array([len(m) for m in misses], dtype=np.int64),
        'misses': np.vstack(misses) if misses else np.zeros((0, 2), np.float32),
    })
    return graph_path, data_path


def read_pose_graph(path: str | Path) -> SerializedGraph:
    """Read what write_pose_graph wrote (or a version-1 file); PoseGraphFileError names the file
    and what is wrong with it."""
    graph_path, data_path = pose_graph_files(path)
    arrays = _read(graph_path, (GRAPH_FORMAT, _OLD_FORMAT))
    if str(arrays['format']) == GRAPH_FORMAT:
        arrays.update({k: v for k, v in _read(data_path, (DATA_FORMAT,)).items() if k != 'format'})
    try:
        count = len(arrays['poses'])
        hits = np.split(arrays['hits'], np.cumsum(arrays['hit_counts'])[:-1])
        misses = np.split(arrays['misses'], np.cumsum(arrays['miss_counts'])[:-1])
        scans = [ScanPoints(o, h, m) for o, h, m in zip(arrays['origins'], hits, misses)]
        edges = [Edge(int(i), int(j), z, info, bool(robust)) for (i, j), z, info, robust in
                 zip(arrays['edge_nodes'], arrays['edge_measurements'], arrays['edge_information'],
                     arrays['edge_robust'])]
        parameters = _parameters(str(arrays['parameters']))
    except (KeyError, ValueError) as exc:
        raise PoseGraphFileError(f'{graph_path}: not a zros pose graph ({exc})') from None
    if not (len(scans) == len(arrays['odom']) == len(arrays['travel']) == count):
        raise PoseGraphFileError(f'{graph_path}: {count} nodes but {len(scans)} scans in {data_path.name}')
    if any(not (0 <= e.i < count and 0 <= e.j < count) for e in edges):
        raise PoseGraphFileError(f'{graph_path}: an edge names a node that is not in the graph')
    return SerializedGraph(arrays['poses'], arrays['odom'], arrays['travel'], scans, edges, parameters)


def _parameters(text: str) -> dict[str, Any]:
    """The parameters as written: JSON (version 2) or a Python dict's repr (version 1)."""
    try:
        return json.loads(text)
    except json.JSONDecodeError:
        return {}                   # version 1 wrote repr(); the parameters are informative only


def _write(path: Path, arrays: dict[str, np.ndarray]) -> None:
    buffer = io.BytesIO()
    np.savez_compressed(buffer, **arrays)
    try:
        path.write_bytes(buffer.getvalue())
    except OSError as exc:
        raise PoseGraphFileError(f'{path}: cannot write the pose graph: {exc.strerror or exc}') from None


def _read(path: Path, formats: tuple[str, ...]) -> dict[str, np.ndarray]:
    try:
        with np.load(path, allow_pickle=False) as data:
            arrays = {name: data[name] for name in data.files}
    except OSError as exc:
        raise PoseGraphFileError(f'{path}: cannot read the pose graph: {exc.strerror or exc}') from None
    except (ValueError, KeyError) as exc:
        raise PoseGraphFileError(f'{path}: not a zros pose graph ({exc})') from None
    if str(arrays.get('format', '')) not in formats:
        raise PoseGraphFileError(f'{path}: not a zros pose graph file (format {formats[0]!r} expected)')
    return arrays
