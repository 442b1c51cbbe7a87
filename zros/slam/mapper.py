"""Online 2D SLAM: scan matching front end, pose graph back end, log-odds map. No Zenoh.

For each scan (with the odometry pose at the scan's time):

1. Front end. The pose predicted by odometry since the last scan is corrected by matching the
   scan against a local map: the likelihood field of the last `scan_buffer_size` keyframes
   (zros.slam.matcher: correlative branch-and-bound search in a small window, then Gauss-Newton;
   a poor match is searched again in the loop closure's wider window before odometry is used).
   So the map does not smear when odometry slips, and map -> odom absorbs the odometry's error.
   Along a direction the scan does not constrain (a featureless corridor: the match's Hessian
   has almost no information along it) the odometry's prediction is kept, not the matcher's
   arbitrary pick; such a match is never taken as a loop closure. Points beyond what the local
   map's scans could reach are left out of the match (zros.slam.scan.within_reach).
2. Keyframes. When the robot has moved `minimum_travel_distance` or turned
   `minimum_travel_heading` since the last keyframe, by the matched pose or by odometry, the
   scan becomes a node of the pose graph, linked to the previous keyframe by the matched
   relative pose.
3. Loop closure. A new keyframe is matched, in a wider window, against a submap of old keyframes
   (at least `loop_search_minimum_travel` of travel ago, within `loop_search_maximum_distance`).
   A match scoring `loop_match_minimum_response` or more adds an edge, unless it would move the
   keyframe (more than two match cells from where the graph has it) on a score below
   `loop_match_correction_response`: look-alike rooms and corridors fit fairly, the same place
   fits almost perfectly (zros.slam.loop_check). The edge's covariance is `loop_sigma_*` plus the match's own (its Hessian), so
   it pulls weakly where the scan pins little down. The graph is then optimised
   (zros.slam.pose_graph): the whole trajectory bends to close the loop. Every edge,
   link or closure, is robust (a Cauchy kernel) and weighted by what matches are truly off by
   (millimetres): a wrong edge then stands out against the many right ones around it and is
   outvoted, where loose weights would let its error spread along the chain and bend the map.
4. Map. Keyframes are cast into a log-odds grid (zros.slam.grid) when the map is asked for;
   keyframes the optimiser moved are taken out at their old pose and put back at the new one.

Localization (after `deserialize(..., localize=True)`, slam_toolbox's localization mode): the
loaded map stays fixed. Each scan is matched, as in step 1, against the map's keyframes nearest
to the robot plus a rolling buffer of the last `scan_buffer_size` localized scans (one every
keyframe step); nothing is added to the graph, so `map_to_odom` is the only output.
`relocalize(pose)` (/initialpose) searches the next scan in the loop closure's window there.

Frames: poses are of the robot's base frame (base_footprint) in `map`; the map frame is where
the first scan was taken (or `initial_pose`). `map_to_odom` is what a SLAM node publishes on TF.
"""
from __future__ import annotations

import math
from collections import deque
from dataclasses import asdict, dataclass, fields
from pathlib import Path
from typing import NamedTuple

import numpy as np

from zros.map_io import OccupancyMap
from zros.slam.geometry import compose, inverse, relative, transform_points
from zros.slam.grid import LogOddsGrid
from zros.slam.match_grid import MatchGrid
from zros.slam.loop_check import closure_information, is_ambiguous
from zros.slam.matcher import SearchWindow, keep_prediction_along, match_scan, weak_directions
from zros.slam.pose_graph import PoseGraph
from zros.slam.scan import ScanPoints, voxel_filter, within_reach
from zros.slam.serialization import (PoseGraphFileError, SerializedGraph, pose_graph_files, read_pose_graph,
                                     write_pose_graph)

__all__ = ['SlamParameters', 'ScanUpdate', 'Slam', 'PoseGraphFileError']


@dataclass(frozen=True)
class SlamParameters:
    """Every tunable, with its unit. Names follow slam_toolbox's where the meaning matches."""
    resolution: float = 0.05                    # [m] map cell
    max_laser_range: float = 20.0               # [m] returns farther than this are free rays only
    missing_data_ray_length: float = 3.0        # [m] free ray given to beams with no return
    minimum_travel_distance: float = 0.2        # [m] between keyframes
    minimum_travel_heading: float = 0.2         # [rad] between keyframes
    scan_buffer_size: int = 10                  # keyframes in the front end's local map
    match_resolution: float = 0.025             # [m] cell of the matching grids
    match_sigma: float = 0.05                   # [m] spread of the likelihood field
    match_point_spacing: float = 0.05           # [m] scan points are thinned to one per square this size
    correlation_search_space_dimension: float = 0.3   # [m] front end window, full width
    coarse_search_angle_offset: float = 0.2     # [rad] front end window, each side
    minimum_match_response: float = 0.3         # front end matches scoring less fall back to odometry
    do_loop_closing: bool = True
    loop_search_maximum_distance: float = 3.0   # [m] from the new keyframe to a candidate
    loop_search_minimum_travel: float = 3.0     # [m] of travel since a candidate was made
    loop_search_space_dimension: float = 1.0    # [m] loop closure window, full width
    loop_search_angle_offset: float = 0.3       # [rad] loop closure window, each side
    loop_match_minimum_response: float = 0.65   # loop closures scoring less are not added
    loop_submap_size: int = 10                  # keyframes each side of the candidate in its submap
    # A closure that moves its keyframe more than two match cells from where the graph has it must
    # score this much: look-alike rooms and corridors fit 0.78-0.90, right matches 0.97-0.99.
    loop_match_correction_response: float = 0.95
    hit_probability: float = 0.7                # occupancy evidence of one return in a cell
    miss_probability: float = 0.3               # evidence of one beam passing through a cell
    occupied_thresh: float = 0.65               # published 100 above this probability
    free_thresh: float = 0.196                  # published 0 below this probability
    # Edge uncertainties: what the matches are truly off by (turtlebot3_house against the truth:
    # links 2 mm / 0.0005 rad median, 5 mm / 0.0014 rad p90; loop closures 3 mm / 0.0006 rad,
    # 6 mm / 0.002 rad). Looser links let one closure's error spread along the whole chain.
    link_sigma_xy: float = 0.005                # [m] keyframe link uncertainty
    link_sigma_yaw: float = 0.002               # [rad]
    loop_sigma_xy: float = 0.01                 # [m] loop closure uncertainty
    loop_sigma_yaw: float = 0.005               # [rad]

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if f.type in ('float', 'int') and not (isinstance(value, (int, float)) and math.isfinite(value)):
                raise ValueError(f'{f.name} must be a number, got {value!r}')
        for name in ('resolution', 'match_resolution', 'match_sigma', 'match_point_spacing', 'max_laser_range',
                     'correlation_search_space_dimension', 'link_sigma_xy', 'link_sigma_yaw', 'loop_sigma_xy',
                     'loop_sigma_yaw'):
            if not getattr(self, name) > 0:
                raise ValueError(f'{name} must be > 0, got {getattr(self, name)}')
        if self.scan_buffer_size < 1:
            raise ValueError(f'scan_buffer_size must be >= 1, got {self.scan_buffer_size}')
        if not 0.0 <= self.free_thresh < self.occupied_thresh <= 1.0:
            raise ValueError('need 0 <= free_thresh < occupied_thresh <= 1')


class ScanUpdate(NamedTuple):
    """What one scan did. pose: base in map; map_to_odom: the correction (both (3,));
    matched: the front end's match was used (not odometry alone); score: its response;
    keyframe: the scan became a node; loop_closed: a loop closure edge was added."""
    pose: np.ndarray
    map_to_odom: np.ndarray
    matched: bool
    score: float
    keyframe: bool
    loop_closed: bool


class _KeyFrame(NamedTuple):
    scan: ScanPoints
    points: np.ndarray          # thinned hits for matching, base frame
    odom: np.ndarray            # odometry pose when taken
    travel: float               # [m] distance travelled before it, along the trajectory


class Slam:
    """The SLAM pipeline (module docstring). Not thread-safe: one caller at a time.

    Args:
        parameters: the tunables.
        initial_pose: the first scan's pose in the map frame.
    """

    def __init__(self, parameters: SlamParameters | None = None, *,
                 initial_pose: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> None:
        self.parameters = parameters or SlamParameters()
        p = self.parameters
        self.graph = PoseGraph()
        self.keyframes: list[_KeyFrame] = []
        self.map_to_odom = np.zeros(3)
        self.loop_closures = 0
        self._grid = LogOddsGrid(p.resolution, hit_probability=p.hit_probability, miss_probability=p.miss_probability)
        self._rendered: dict[int, np.ndarray] = {}
        self._initial_pose = np.asarray(initial_pose, dtype=np.float64)
        self._pose: np.ndarray | None = None        # last scan's pose in map
        self._odom: np.ndarray | None = None        # and its odometry pose
        self._anchor: int | None = None             # the keyframe the next one links to
        self._session_start = 0                     # first keyframe of this session (after a load)
        self._travel = 0.0
        self._local: MatchGrid | None = None
        #: The front end's local map's scans: sensor positions (K, 2) in map and farthest returns (K,).
        self._local_reach: tuple[np.ndarray, np.ndarray] | None = None
        self._localizing = False
        #: Localization's rolling buffer: (pose, hits in the map frame) of the last scans.
        self._buffer: deque[tuple[np.ndarray, np.ndarray]] = deque(maxlen=self.parameters.scan_buffer_size)
        self._front = SearchWindow(p.correlation_search_space_dimension / 2.0, p.coarse_search_angle_offset)
        self._loop = SearchWindow(p.loop_search_space_dimension / 2.0, p.loop_search_angle_offset)
        self._link_info = np.diag([p.link_sigma_xy ** -2, p.link_sigma_xy ** -2, p.link_sigma_yaw ** -2])
        self._loop_info = np.diag([p.loop_sigma_xy ** -2, p.loop_sigma_xy ** -2, p.loop_sigma_yaw ** -2])

    # -- the pipeline ---------------------------------------------------------------------------
    def process_scan(self, odom_pose: np.ndarray, scan: ScanPoints) -> ScanUpdate:
        """Take one scan (in the base frame, with the odometry pose at its time)."""
        p = self.parameters
        odom = np.asarray(odom_pose, dtype=np.float64)
        points = voxel_filter(scan.hits, p.match_point_spacing)
        matched, score = False, 0.0
        if self._pose is None:                  # the first scan; after a load, find it in the old map
            pose, window = self._initial_pose.copy(), self._loop
        else:
            pose, window = compose(self._pose, relative(self._odom, odom)), self._front
        if self._local is not None and len(points) >= 3:
            usable = self._reachable(points, pose)
            result = match_scan(self._local, usable, pose, window, min_score=p.minimum_match_response)
            if result.score < p.minimum_match_response and window is self._front:
                # Odometry is off by more than the window (a bump, a spin on the spot): look wider.
                result = match_scan(self._local, usable, pose, self._loop, min_score=p.minimum_match_response)
            score = result.score
            if score >= p.minimum_match_response:
                # In a corridor the scan fixes the pose across it, not along it: keep odometry there.
                pose, matched = keep_prediction_along(result.pose, pose, weak_directions(result.information)), True
        if self._pose is not None:
            self._travel += float(np.hypot(*(pose[:2] - self._pose[:2])))
        self._pose, self._odom = pose, odom
        keyframe = loop_closed = False
        if self._localizing:
            if matched:
                self._localize(pose, scan)
        elif self._is_keyframe(pose, odom) and len(points) >= 3:
            keyframe = True
            loop_closed = self._add_keyframe(pose, odom, scan, points)
        self.map_to_odom = compose(self._pose, inverse(odom))
        return ScanUpdate(self._pose.copy(), self.map_to_odom.copy(), matched, score, keyframe, loop_closed)

    def _is_keyframe(self, pose: np.ndarray, odom: np.ndarray) -> bool:
        """A keyframe's step since the last one, by the matched pose or by odometry (slam_toolbox
        counts the travel in odometry). Odometry alone keeps the local map growing when the front
        end is stuck: in a long corridor, a scan that reaches past the last keyframe's walls fits
        best pulled back onto them, and if the estimate never moves a step no keyframe extends
        the map, so the next scan is pulled back further (the bighouse: 0.9 m over 25 scans)."""
        if self._anchor is None or len(self.keyframes) == self._session_start:
            return True
        return (self._moved_enough(self.graph.poses[len(self.keyframes) - 1], pose)
                or self._moved_enough(self.keyframes[-1].odom, odom))

    def _moved_enough(self, last: np.ndarray, pose: np.ndarray) -> bool:
        """Whether `pose` is a keyframe's step (minimum_travel_distance or _heading) from `last`."""
        p = self.parameters
        moved = relative(last, pose)
        return bool(math.hypot(moved[0], moved[1]) >= p.minimum_travel_distance
                    or abs(moved[2]) >= p.minimum_travel_heading)

    def _add_keyframe(self, pose: np.ndarray, odom: np.ndarray, scan: ScanPoints, points: np.ndarray) -> bool:
        node = self.graph.add_node(pose)
        self.keyframes.append(_KeyFrame(scan, points, odom.copy(), self._travel))
        if self._anchor is not None:
            # Robust, like the closures: a link the front end got wrong (a slide along a long room,
            # a snap in yaw) is outvoted by the closures around it instead of bending the chain.
            self.graph.add_edge(self._anchor, node, relative(self.graph.poses[self._anchor], pose), self._link_info,
                                robust=True)
        self._anchor = node
        closed = self.parameters.do_loop_closing and self._close_loop(node, points)
        if closed:
            self.graph.optimize()
            self._pose = self.graph.poses[node].copy()
        self._set_local_map(self._local_nodes(self._pose))
        return closed

    def _local_nodes(self, pose: np.ndarray) -> np.ndarray:
        """The front end's local map: this session's last keyframes, topped up (after a load)
        with the old keyframes nearest to the current pose."""
        p = self.parameters
        count = len(self.keyframes)
        recent = np.arange(max(self._session_start, count - p.scan_buffer_size), count)
        missing = p.scan_buffer_size - len(recent)
        if missing > 0 and self._session_start > 0:
            old = self.graph.poses[:self._session_start, :2]
            nearest = np.argsort(np.hypot(*(old - pose[:2]).T))[:missing]
            recent = np.concatenate([nearest, recent])
        return recent

    def _set_local_map(self, nodes: np.ndarray) -> None:
        """The front end's local map from `nodes`, and how far their scans reached."""
        self._local = self._match_grid(nodes) if len(nodes) else None
        scans = [self.keyframes[n].scan for n in nodes]
        origins = np.array([transform_points(self.graph.poses[n], s.origin[None, :])[0] for n, s in zip(nodes, scans)])
        reach = np.array([float(np.hypot(*(s.hits - s.origin).T).max()) if len(s.hits) else 0.0 for s in scans])
        self._local_reach = (origins.reshape(-1, 2), reach)

    def _reachable(self, points: np.ndarray, pose: np.ndarray) -> np.ndarray:
        """The scan points (base frame) at `pose` that the local map's scans could have seen
        (zros.slam.scan.within_reach); all of them if fewer than three are."""
        if self._local_reach is None:
            return points
        keep = within_reach(transform_points(pose, points), *self._local_reach)
        return points[keep] if keep.sum() >= 3 else points

    def _match_grid(self, nodes: np.ndarray, extra: list[np.ndarray] | None = None) -> MatchGrid | None:
        """The likelihood field of the given keyframes' points at their graph poses (and of
        `extra` point clouds already in the map frame)."""
        clouds = [transform_points(self.graph.poses[n], self.keyframes[n].scan.hits) for n in nodes] + (extra or [])
        clouds = [c for c in clouds if len(c)]
        if not clouds:
            return None
        p = self.parameters
        return MatchGrid(np.vstack(clouds), p.match_resolution, sigma=p.match_sigma)

    def _close_loop(self, node: int, points: np.ndarray) -> bool:
        """Try one loop closure from `node` to the nearest old keyframe; True if an edge was added."""
        p = self.parameters
        poses = self.graph.poses
        travel = np.array([k.travel for k in self.keyframes])
        pose = poses[node]
        distance = np.hypot(*(poses[:, :2] - pose[:2]).T)
        old = (travel[node] - travel >= p.loop_search_minimum_travel) | (np.arange(len(travel)) < self._session_start)
        old[node] = False
        candidates = np.flatnonzero(old & (distance <= p.loop_search_maximum_distance))
        if len(candidates) == 0:
            return False
        target = int(candidates[np.argmin(distance[candidates])])
        around = np.arange(max(0, target - p.loop_submap_size), min(len(travel), target + p.loop_submap_size + 1))
        grid = self._match_grid(around[old[around]])
        if grid is None:
            return False
        result = match_scan(grid, points, pose, self._loop, min_score=p.loop_match_minimum_response)
        # No match, or one that slides freely along a corridor: no evidence of a loop. A direction
        # only weakly held (matcher.CORRIDOR_INFORMATION) is not a reason to drop it: the closure's
        # covariance, from the same Hessian, already makes it pull little that way.
        if result.score < p.loop_match_minimum_response or len(weak_directions(result.information, anisotropy=0.0)):
            return False
        if is_ambiguous(result.score, float(np.hypot(*(result.pose[:2] - pose[:2]))),
                        min_response=p.loop_match_correction_response, tolerance=2.0 * p.match_resolution):
            return False            # a fair fit elsewhere: a look-alike, not evidence to bend the graph
        information = closure_information(result.information, self._loop_info, p.match_sigma)
        self.graph.add_edge(target, node, relative(poses[target], result.pose), information, robust=True)
        self.loop_closures += 1
        return True

    # -- the map --------------------------------------------------------------------------------
    def occupancy_map(self) -> OccupancyMap:
        """The current map (trinary: 100, 0, -1), in the map frame. Keyframes moved by the pose
        graph since the last call are re-cast; new ones are added."""
        p = self.parameters
        tolerance_xy, tolerance_yaw = p.resolution / 4.0, p.resolution / 4.0 / max(p.missing_data_ray_length, 1.0)
        for node, keyframe in enumerate(self.keyframes):
            pose = self.graph.poses[node]
            old = self._rendered.get(node)
            if old is not None:
                moved = relative(old, pose)
                if math.hypot(moved[0], moved[1]) <= tolerance_xy and abs(moved[2]) <= tolerance_yaw:
                    continue
                self._grid.add_scan(old, keyframe.scan, weight=-1.0)
            self._grid.add_scan(pose, keyframe.scan)
            self._rendered[node] = pose.copy()
        return self._grid.occupancy(occupied_thresh=p.occupied_thresh, free_thresh=p.free_thresh)

    @property
    def pose(self) -> np.ndarray | None:
        """The last scan's pose of the robot in the map, or None before the first scan."""
        return None if self._pose is None else self._pose.copy()

    def trajectory(self) -> np.ndarray:
        """(N, 3) keyframe poses in the map, optimised."""
        return self.graph.poses.copy()

    # -- saving and loading the pose graph -------------------------------------------------------
    def serialize(self, path: str | Path) -> tuple[Path, Path]:
        """Write the pose graph to `path` + '.posegraph' and its scans to `path` + '.data'
        (slam_toolbox's serialize_map; zros.slam.serialization); returns both files."""
        return write_pose_graph(path, SerializedGraph(
            self.graph.poses, np.array([k.odom for k in self.keyframes]).reshape(-1, 3),
            np.array([k.travel for k in self.keyframes]), [k.scan for k in self.keyframes], list(self.graph.edges),
            asdict(self.parameters)))

    def deserialize(self, path: str | Path, *, pose: tuple[float, float, float] | None = None,
                    localize: bool = False) -> Path:
        """Replace the graph with a serialized one (`path` with or without '.posegraph').

        Mapping (`localize` False) goes on from `pose` in its map (default: its first node,
        slam_toolbox's START_AT_FIRST_NODE; a pose is START_AT_GIVEN_POSE), new keyframes joining
        the old graph. Localization (LOCALIZE_AT_POSE) keeps the map fixed: scans are matched
        against it near `pose` and only kept in a rolling buffer (module docstring). Keeps this
        instance's parameters; returns the .posegraph file read."""
        saved = read_pose_graph(path)
        graph = PoseGraph()
        for node_pose in saved.poses:
            graph.add_node(node_pose)
        for edge in saved.edges:
            graph.add_edge(edge.i, edge.j, edge.measurement, edge.information, robust=edge.robust)
        spacing = self.parameters.match_point_spacing
        self.keyframes = [_KeyFrame(scan, voxel_filter(scan.hits, spacing), odom, float(travel))
                          for scan, odom, travel in zip(saved.scans, saved.odom, saved.travel)]
        self.graph = graph
        self._grid.clear()
        self._rendered.clear()
        count = len(self.keyframes)
        self._session_start = count
        self._localizing = localize
        self._travel = (float(saved.travel.max()) if count else 0.0) + 2.0 * self.parameters.loop_search_minimum_travel
        self.relocalize(pose if pose is not None else (graph.poses[0] if count else self._initial_pose))
        return pose_graph_files(path)[0]

    # -- localization ---------------------------------------------------------------------------
    @property
    def localizing(self) -> bool:
        """Whether scans localize in a fixed map (after deserialize(..., localize=True))."""
        return self._localizing

    def relocalize(self, pose: tuple[float, float, float] | np.ndarray) -> None:
        """Take the next scan to be near `pose` in the map (a loop-closure-wide search around
        it): where a map is loaded, and what /initialpose does. Empties the localization buffer."""
        self._initial_pose = np.asarray(pose, dtype=np.float64).copy()
        self._pose, self._odom = None, None
        self._buffer.clear()
        count = len(self.keyframes)
        if not self._localizing:
            self._anchor = int(np.argmin(np.hypot(*(self.graph.poses[:, :2] - self._initial_pose[:2]).T))) \
                if count else None
            self._set_local_map(self._local_nodes(self._initial_pose) if count else np.zeros(0, dtype=np.int64))
        else:
            self._local, self._local_reach = self._localization_grid(self._initial_pose), None

    def clear_localization_buffer(self) -> None:
        """Forget the recent scans localization matches against (slam_toolbox's
        clear_localization_buffer); the map's own keyframes stay."""
        self._buffer.clear()
        if self._localizing and self._pose is not None:
            self._local = self._localization_grid(self._pose)

    def _localize(self, pose: np.ndarray, scan: ScanPoints) -> None:
        """After a localized scan: every keyframe-sized step, keep it in the rolling buffer and
        rebuild the local map around the new pose. The graph and the map do not change."""
        if self._buffer and not self._moved_enough(self._buffer[-1][0], pose):
            return
        self._buffer.append((pose.copy(), transform_points(pose, scan.hits)))
        self._local = self._localization_grid(pose)

    def _localization_grid(self, pose: np.ndarray) -> MatchGrid | None:
        """The map's keyframes nearest to `pose` (2 x loop_submap_size of them) and the buffer."""
        if not self.keyframes:
            return None
        old = np.argsort(np.hypot(*(self.graph.poses[:, :2] - pose[:2]).T))[:2 * self.parameters.loop_submap_size]
        return self._match_grid(old, [cloud for _, cloud in self._buffer])
