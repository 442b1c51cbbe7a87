"""SLAM benchmark: accuracy of zros.slam against the simulator's ground truth, and its cost.

    python benchmarks/slam.py               # every world, about 15 minutes on a quiet machine
    python benchmarks/slam.py --world turtlebot3_world --map /tmp/map   # also save the map
    python benchmarks/slam.py --world turtlebot3_house --overlay /tmp/house.png   # map over truth
    python benchmarks/slam.py --json out.json
    python benchmarks/slam.py --world turtlebot3_house --set do_loop_closing=false   # compare a parameter
    python benchmarks/slam.py --world turtlebot3_bighouse --via=-2,-1 --via=1,-4.5 ... --via=-2,-1 \
        --map /tmp/bh --map-from-truth    # another drive; save the map drawn from the true poses

Goals (issue 16, docs/architecture.md §9): in turtlebot3_world, trajectory error (ATE RMSE) <= 5 cm and at
least 5x better than odometry alone; map: >= 95 % of the visible true wall cells found within
one cell, <= 2 % of the occupied map cells free in truth; cost: keeps up with the 5 Hz lidar at
5x real time on one core (>= 25 scans/s, map updates included). House: ATE <= 10 cm. Issue 34:
the same map goals and ATE <= 5 cm in turtlebot3_house and turtlebot3_bighouse; `corridor` (a
20 m featureless corridor with doors) is the case where the scan cannot fix the position along
the corridor.

What runs: zros.sim's Simulation (no Zenoh, no processes), a burger following a fixed route
(shortest paths through fixed via points, planned on the world's raster with 0.2 m clearance,
followed by a pure-pursuit controller on the true pose, 0.2 m/s) as fast as the machine
allows. Every simulated 0.2 s a lidar scan and the odometry pose go to zros.slam.Slam, as the
SLAM node feeds it; every simulated second the map is produced, as the node publishes it.

Odometry noise, "realistic": the wheel encoders slip (zros.sim's `slip_stddev` 0.01 m per
sqrt(m), five times the simulator's default) and the odometry model is miscalibrated as a real
robot's is: every increment's travel is scaled by 1.01 and its rotation by 1.02 (a wheel
diameter and a wheel separation off by 1 % and 2 %), integrated like the diff-drive plugin does.

Reported: ATE RMSE (and maximum, final, final heading) of SLAM's map -> base_footprint at every
scan, and of odometry alone, both in the map frame (where the robot started; no alignment is
fitted); map quality (zros.sim.evaluation), and the same for a map made from the true poses
with the same scans (the metric's floor: what a SLAM without pose error would score, so a miss
is told apart from a strict metric); the optimised keyframe poses' error (what the map is drawn
from) and each loop closure's error against the true relative pose of its two keyframes (false
matches are decimetres off, right ones millimetres); cost as scans per CPU second of this thread
(`time.thread_time`, map updates included) and the CPU share at 5 Hz scans at 1x and 5x.
"""
from __future__ import annotations

import argparse
import json
from dataclasses import fields
import math
import platform
import sys
import time
from pathlib import Path

import numpy as np
from scipy import ndimage
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

REPO = Path(__file__).resolve().parents[1]
if str(REPO) not in sys.path:
    sys.path.insert(0, str(REPO))

from zros.sim import LDS_01, Simulation, load_world, rasterize  # noqa: E402
from zros.sim.raycast import cast_fan  # noqa: E402
from zros.slam import Slam, SlamParameters, scan_points  # noqa: E402
from zros.slam.grid import LogOddsGrid  # noqa: E402
from zros.slam.scan import ScanPoints  # noqa: E402
from zros.image_io import encode_png  # noqa: E402
from zros.sim.evaluation import (edge_errors, in_map_frame, map_quality, overlay, seen_walls,  # noqa: E402
                                 trajectory_error)
from zros.slam.geometry import compose, relative  # noqa: E402

GOALS = {'ate_m': 0.05, 'ate_ratio': 5.0, 'wall_recall': 0.95, 'false_occupied': 0.02, 'scans_per_s': 25.0,
         'house_ate_m': 0.10}
SCAN_PERIOD = 0.2           # [s] 5 Hz lidar
CONTROL_PERIOD = 0.1        # [s]
MAP_PERIOD = 1.0            # [s] of simulated time between map updates (Cartographer's publish period)
SPEED = 0.2                 # [m/s]
CLEARANCE = 0.2             # [m] from obstacles for the planned route
SLIP = 0.01                 # [m per sqrt(m)]
DISTANCE_SCALE, ROTATION_SCALE = 1.01, 1.02
SENSOR = (LDS_01.angle_min, LDS_01.angle_increment, LDS_01.range_min, LDS_01.range_max)

# Via points [m, world frame]: a loop round the pillars and lanes between them (turtlebot3_world),
# rooms and doors (turtlebot3_house); each ends where it began, so the loop must close.
ROUTES = {
    'turtlebot3_world': [(-2.0, -0.5), (-1.65, -1.65), (1.65, -1.65), (1.65, 1.65), (-1.65, 1.65),
                         (-1.65, -0.55), (0.55, -0.55), (0.55, 0.55), (-0.55, 0.55), (-0.55, -1.65),
                         (1.65, -1.65), (1.65, 1.65), (-1.65, 1.65), (-2.0, -0.5)],
    'turtlebot3_house': [(-2.0, -0.5), (-3.5, -1.5), (-1.0, -2.5), (2.0, -1.5), (1.15, 0.35), (-1.0, 0.4),
                         (-2.7, 1.2), (-4.2, 3.3), (-6.3, 3.3), (-4.2, 3.3), (-1.0, 4.2), (-0.9, 1.5),
                         (3.5, 0.4), (5.5, 4.0), (3.2, 4.6), (1.1, 4.0), (3.2, 4.6), (6.5, 2.0),
                         (6.2, -1.0), (6.2, -3.5), (6.2, -1.0), (3.5, 0.4), (1.15, 0.35), (2.0, -1.5),
                         (-2.0, -0.5)],
    # issue 34: the 24 m x 16 m bighouse, driven into each room to its deepest free point (by a
    # distance transform of the truth raster) and back out along the corridor, as someone mapping
    # it by teleop would; looking in from the doors only left half the house unmapped for AMCL
    'turtlebot3_bighouse': [(-2.0, -1.0), (1.0, -4.5), (3.0, -1.0), (3.0, 1.7), (1.5, 5.5), (3.0, 1.7),
                            (8.0, -1.0), (7.7, 4.5), (8.0, -1.0), (6.5, -4.0), (10.3, -6.3), (6.5, -4.0),
                            (11.0, -1.0), (-2.0, -1.0), (-4.2, 5.7), (-2.0, -1.0), (-5.0, -3.5),
                            (-6.5, -6.5), (-5.0, -3.5), (-9.0, -1.0), (-7.8, 1.8), (-10.7, 5.3), (-7.8, 1.8),
                            (-9.0, -1.0), (-10.0, -5.3), (-9.0, -1.0), (-2.0, -1.0)],
    # issue 34: the 20 m featureless corridor, to its far end through two rooms and back
    'corridor': [(-8.5, 0.0), (-6.0, 2.5), (-6.0, 0.0), (8.5, 0.0), (6.0, -2.5), (6.0, 0.0), (-8.5, 0.0)],
}


# -- the route ----------------------------------------------------------------------------------
def plan_route(world_name: str, vias: list[tuple[float, float]], resolution: float = 0.05) -> np.ndarray:
    """(N, 2) points [m] every cell along shortest paths through `vias`, keeping CLEARANCE."""
    raster = rasterize(load_world(world_name), resolution, margin=4.0)
    distance = ndimage.distance_transform_edt(~raster.cells) * resolution
    free = distance > CLEARANCE
    height, width = free.shape
    index = np.arange(height * width).reshape(height, width)
    rows, cols, weights = [], [], []
    for dr, dc in ((0, 1), (1, 0), (1, 1), (1, -1)):              # each undirected neighbour pair once
        c0, c1 = max(0, -dc), width - max(0, dc)
        ok = free[:height - dr, c0:c1] & free[dr:, c0 + dc:c1 + dc]
        rows.append(index[:height - dr, c0:c1][ok])
        cols.append(index[dr:, c0 + dc:c1 + dc][ok])
        weights.append(np.full(int(ok.sum()), math.hypot(dr, dc)))
    graph = csr_matrix((np.concatenate(weights), (np.concatenate(rows), np.concatenate(cols))),
                       shape=(height * width, height * width))
    path: list[int] = []
    for (x0, y0), (x1, y1) in zip(vias[:-1], vias[1:]):
        start = index[raster.cell_of(x0, y0)]
        goal = index[raster.cell_of(x1, y1)]
        if not (free.ravel()[start] and free.ravel()[goal]):
            raise ValueError(f'via point ({x0}, {y0}) or ({x1}, {y1}) is within {CLEARANCE} m of an obstacle')
        _, predecessors = dijkstra(graph, directed=False, indices=start, return_predecessors=True)
        leg = [goal]
        while leg[-1] != start:
            leg.append(int(predecessors[leg[-1]]))
            if leg[-1] < 0:
                raise ValueError(f'no path from ({x0}, {y0}) to ({x1}, {y1})')
        path.extend(reversed(leg[:-1] if path else leg))
    cells = np.array(path)
    return np.column_stack([raster.origin[0] + (cells % width + 0.5) * resolution,
                            raster.origin[1] + (cells // width + 0.5) * resolution])


def pure_pursuit(pose: tuple[float, float, float], route: np.ndarray, progress: int,
                 lookahead: float = 0.3) -> tuple[float, float, int]:
    """(linear, angular, new progress index) to follow `route` from `pose`."""
    x, y, yaw = pose
    window = route[progress:progress + 40]
    nearest = progress + int(np.argmin(np.hypot(window[:, 0] - x, window[:, 1] - y)))
    ahead = nearest
    while ahead < len(route) - 1 and math.hypot(route[ahead, 0] - x, route[ahead, 1] - y) < lookahead:
        ahead += 1
    tx, ty = route[ahead]
    heading = math.remainder(math.atan2(ty - y, tx - x) - yaw, 2 * math.pi)
    if abs(heading) > 0.8:
        return 0.0, math.copysign(1.0, heading), nearest
    distance = math.hypot(tx - x, ty - y)
    curvature = 2.0 * math.sin(heading) / max(distance, 1e-6)
    return SPEED, SPEED * curvature, nearest


# -- odometry as a real robot's ----------------------------------------------------------------
class BiasedOdometry:
    """Re-integrates the simulator's encoder odometry with scale errors (module docstring)."""

    def __init__(self) -> None:
        self.pose = np.zeros(3)
        self._last = np.zeros(3)

    def update(self, sim_odom: np.ndarray) -> np.ndarray:
        step = relative(self._last, sim_odom)
        distance = math.hypot(step[0], step[1]) * DISTANCE_SCALE * (1 if step[0] >= 0 else -1)
        turn = step[2] * ROTATION_SCALE
        heading = self.pose[2] + turn / 2.0
        self.pose = np.array([self.pose[0] + distance * math.cos(heading),
                              self.pose[1] + distance * math.sin(heading),
                              math.remainder(self.pose[2] + turn, 2 * math.pi)])
        self._last = sim_odom.copy()
        return self.pose.copy()


def true_ray_ends(world: object, sensor: tuple[float, float, float]) -> np.ndarray:
    """Where the lidar's beams end without noise, a millimetre into what they hit: (N, 2)."""
    x, y, yaw = sensor
    angles = yaw + LDS_01.angle_min + LDS_01.angle_increment * np.arange(LDS_01.samples)
    ranges = cast_fan((x, y), angles[0], LDS_01.angle_increment, LDS_01.samples, world.edges, world.circles,
                      LDS_01.range_max)
    hit = np.isfinite(ranges) & (ranges >= LDS_01.range_min)
    reach = ranges[hit] + 0.001
    return np.column_stack([x + reach * np.cos(angles[hit]), y + reach * np.sin(angles[hit])])


def _add_known_pose_scan(grid: LogOddsGrid, last: np.ndarray | None, pose: np.ndarray,
                         points: ScanPoints) -> np.ndarray | None:
    """Map with the true poses (the reference that tells the metric's floor from SLAM's error):
    a scan goes in when the robot moved as far as SLAM's keyframe rule asks. Returns the last pose used."""
    if last is not None:
        moved = relative(last, pose)
        if math.hypot(moved[0], moved[1]) < 0.2 and abs(moved[2]) < 0.2:
            return last
    grid.add_scan(pose, points)
    return pose


# -- one run -----------------------------------------------------------------------------------
def run(world_name: str, *, seed: int = 1, save_map: str | None = None, overlay_png: str | None = None,
        parameters: SlamParameters | None = None, vias: list[tuple[float, float]] | None = None,
        map_from_truth: bool = False) -> dict:
    """One drive through `vias` (default: ROUTES[world_name]); `save_map` writes SLAM's map, or with
    `map_from_truth` the map drawn from the true poses (the same scans), to tell what the map's
    coverage costs navigation from what SLAM's pose error costs it."""
    world = load_world(world_name)
    route = plan_route(world_name, vias or ROUTES[world_name])
    sim = Simulation(world, seed=seed)
    spawn = world.spawn
    robot = sim.add_robot('burger', (spawn.x, spawn.y, spawn.yaw), slip_stddev=SLIP, odometry='encoder')
    spawn_pose = np.array([spawn.x, spawn.y, spawn.yaw])
    slam = Slam(parameters)
    odometry = BiasedOdometry()
    estimates, odoms, truths, rays, keyframe_scans = [], [], [], [], []
    known = LogOddsGrid(slam.parameters.resolution, hit_probability=slam.parameters.hit_probability,
                        miss_probability=slam.parameters.miss_probability)
    known_last: np.ndarray | None = None
    slam_cpu = 0.0
    progress, scans, next_map = 0, 0, 0.0
    steps_per_scan = int(round(SCAN_PERIOD / CONTROL_PERIOD))
    wall0 = time.perf_counter()
    while progress < len(route) - 5 and sim.time < 900.0:
        if scans:
            for _ in range(steps_per_scan):
                p = robot.pose
                linear, angular, progress = pure_pursuit((p.x, p.y, p.yaw), route, progress)
                robot.command(linear, angular)
                sim.step(CONTROL_PERIOD)
        o = robot.odometry()
        odom = odometry.update(np.array([o.x, o.y, o.yaw]))
        ranges = robot.scan()
        truth = robot.pose
        cpu0 = time.thread_time()
        points = scan_points(ranges, SENSOR[0], SENSOR[1], range_min=SENSOR[2], range_max=SENSOR[3],
                             sensor_pose=(-0.032, 0.0, 0.0))
        update = slam.process_scan(odom, points)
        if sim.time >= next_map:
            slam.occupancy_map()
            next_map += MAP_PERIOD
        slam_cpu += time.thread_time() - cpu0
        scans += 1
        estimates.append(update.pose)
        if update.keyframe:
            keyframe_scans.append(scans - 1)
        odoms.append(odom)
        truths.append((truth.x, truth.y, truth.yaw))
        known_last = _add_known_pose_scan(known, known_last, in_map_frame(np.array(truths[-1]), spawn_pose), points)
        rays.append(true_ray_ends(world, robot.sensor_pose(robot.spec.lidar_mount)))
    wall = time.perf_counter() - wall0
    cpu0 = time.thread_time()
    grid = slam.occupancy_map()
    slam_cpu += time.thread_time() - cpu0
    truth_map = in_map_frame(np.array(truths), spawn_pose)
    ate = trajectory_error(np.array(estimates), truth_map)
    ate_odom = trajectory_error(np.array(odoms), truth_map)
    keyframe_truth = truth_map[keyframe_scans]
    keyframe_ate = trajectory_error(slam.trajectory(), keyframe_truth)
    closures = _closure_errors(slam, keyframe_truth)
    truth_raster = rasterize(world, grid.resolution)
    walls = seen_walls(truth_raster, np.vstack(rays))
    quality = map_quality(grid, spawn_pose, truth_raster, walls)
    floor = map_quality(known.occupancy(occupied_thresh=slam.parameters.occupied_thresh,
                                        free_thresh=slam.parameters.free_thresh), spawn_pose, truth_raster, walls)
    if overlay_png:
        Path(overlay_png).write_bytes(encode_png(overlay(grid, spawn_pose, truth_raster, walls, scale=3)))
    if save_map:
        from zros.map_io import OccupancyMap, save_map as write_map
        saved = known.occupancy(occupied_thresh=slam.parameters.occupied_thresh,
                                free_thresh=slam.parameters.free_thresh) if map_from_truth else grid
        x, y, yaw = compose(spawn_pose, np.array(saved.origin))
        write_map(OccupancyMap(saved.data, saved.resolution, (float(x), float(y), float(yaw))), save_map)
    per_scan = slam_cpu / scans
    return {
        'world': world_name, 'sim_time_s': round(sim.time, 1), 'distance_m': round(float(np.sum(
            np.hypot(*np.diff(np.array(truths)[:, :2], axis=0).T))), 1),
        'scans': scans, 'keyframes': len(slam.keyframes), 'loop_closures': slam.loop_closures,
        'keyframe_rmse_m': keyframe_ate.rmse, 'keyframe_max_m': keyframe_ate.maximum, **closures,
        'ate_rmse_m': ate.rmse, 'ate_max_m': ate.maximum, 'final_error_m': ate.final,
        'final_heading_deg': math.degrees(ate.final_heading),
        'odom_ate_rmse_m': ate_odom.rmse, 'odom_final_error_m': ate_odom.final,
        'wall_recall': quality.wall_recall, 'false_occupied': quality.false_occupied,
        'false_occupied_beyond_one_cell': quality.false_occupied_beyond_one_cell,
        'known_poses_wall_recall': floor.wall_recall, 'known_poses_false_occupied': floor.false_occupied,
        'known_poses_false_occupied_beyond_one_cell': floor.false_occupied_beyond_one_cell,
        'wall_cells': quality.wall_cells, 'occupied_cells': quality.occupied_cells,
        'scans_per_cpu_s': 1.0 / per_scan, 'cpu_share_1x': per_scan * 5.0, 'cpu_share_5x': per_scan * 25.0,
        'wall_s': round(wall, 1),
    }


def _closure_errors(slam: Slam, keyframe_truth: np.ndarray) -> dict:
    """How far the loop closures' measurements are from the true relative poses: many
    decimetre errors mean false matches, centimetre errors that still bend the map mean weights."""
    loops = [e for e in slam.graph.edges if e.robust]
    if not loops:
        return {'closure_error_median_m': math.nan, 'closure_error_max_m': math.nan, 'closures_off_10cm': 0}
    error = edge_errors(np.array([e.i for e in loops]), np.array([e.j for e in loops]),
                        np.array([e.measurement for e in loops]), keyframe_truth)
    return {'closure_error_median_m': float(np.median(error[:, 0])), 'closure_error_max_m': float(error[:, 0].max()),
            'closures_off_10cm': int((error[:, 0] > 0.1).sum())}


def print_table(results: list[dict]) -> None:
    rows = [
        ('ATE RMSE, SLAM [m]', 'ate_rmse_m', '{:.3f}', 'world <= 0.05, house <= 0.10'),
        ('ATE RMSE, odometry [m]', 'odom_ate_rmse_m', '{:.3f}', ''),
        ('odometry / SLAM', None, '{:.1f}x', '>= 5x'),
        ('ATE max, SLAM [m]', 'ate_max_m', '{:.3f}', ''),
        ('keyframes optimised, RMS [m]', 'keyframe_rmse_m', '{:.3f}', 'what the map is drawn from'),
        ('keyframes optimised, max [m]', 'keyframe_max_m', '{:.3f}', ''),
        ('loop closure error, median [m]', 'closure_error_median_m', '{:.3f}', 'against the true relative pose'),
        ('loop closure error, max [m]', 'closure_error_max_m', '{:.3f}', ''),
        ('closures off by > 10 cm', 'closures_off_10cm', '{}', ''),
        ('final heading error [deg]', 'final_heading_deg', '{:.2f}', '<= 2'),
        ('walls found within 1 cell', 'wall_recall', '{:.1%}', '>= 95%'),
        ('occupied cells free in truth', 'false_occupied', '{:.1%}', '<= 2%'),
        ('... with no true obstacle within 1 cell', 'false_occupied_beyond_one_cell', '{:.1%}', '<= 2%'),
        ('same three, map from the true poses', None, '', 'the metric\'s floor'),
        ('scans per CPU second', 'scans_per_cpu_s', '{:.0f}', '>= 25 (5 Hz at 5x)'),
        ('CPU share at 5 Hz, 1x', 'cpu_share_1x', '{:.1%}', ''),
        ('CPU share at 5 Hz, 5x', 'cpu_share_5x', '{:.1%}', '<= 100%'),
        ('route [m] / sim time [s]', None, '', ''),
        ('scans / keyframes / loop closures', None, '', ''),
    ]
    header = f"| {'measure':<34} | " + ' | '.join(f'{r["world"]:<17}' for r in results) + ' | goal |'
    print(header)
    print('|' + '---|' * (len(results) + 2))
    for label, key, fmt, goal in rows:
        cells = []
        for r in results:
            if key:
                cells.append(fmt.format(r[key]))
            elif label.startswith('odometry'):
                cells.append(fmt.format(r['odom_ate_rmse_m'] / max(r['ate_rmse_m'], 1e-9)))
            elif label.startswith('same three'):
                cells.append(f"{r['known_poses_wall_recall']:.1%} / {r['known_poses_false_occupied']:.1%} / "
                             f"{r['known_poses_false_occupied_beyond_one_cell']:.1%}")
            elif label.startswith('route'):
                cells.append(f"{r['distance_m']} / {r['sim_time_s']}")
            else:
                cells.append(f"{r['scans']} / {r['keyframes']} / {r['loop_closures']}")
        print(f'| {label:<34} | ' + ' | '.join(f'{c:<17}' for c in cells) + f' | {goal} |')


def _parameter(text: str) -> tuple[str, object]:
    """'name=value' as a SlamParameters keyword: value read as JSON (numbers, true/false)."""
    name, sep, value = text.partition('=')
    if not sep:
        raise ValueError(f'--set takes NAME=VALUE, got {text!r}')
    if name not in {f.name for f in fields(SlamParameters)}:
        raise ValueError(f'--set {name}: not a SLAM parameter (zros.slam.SlamParameters)')
    try:
        return name, json.loads(value.lower() if value.lower() in ('true', 'false') else value)
    except json.JSONDecodeError:
        raise ValueError(f'--set {name}: {value!r} is not a number or true/false') from None


def _via(text: str) -> tuple[float, float]:
    """'x,y' [m] as a via point."""
    try:
        x, y = (float(v) for v in text.split(','))
    except ValueError:
        raise argparse.ArgumentTypeError(f'a via point is X,Y in metres, got {text!r}') from None
    return x, y


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--world', action='append', choices=sorted(ROUTES), help='default: both')
    parser.add_argument('--seed', type=int, default=1)
    parser.add_argument('--map', help='save the (last) map to this name (.yaml + .pgm), in the world frame')
    parser.add_argument('--overlay', metavar='PNG', help='draw the (last) map over the truth raster here '
                        '(zros.sim.evaluation.overlay: black walls found, blue missed, red false occupied)')
    parser.add_argument('--map-from-truth', action='store_true',
                        help='--map saves the map drawn from the true poses (same scans) instead of SLAM\'s')
    parser.add_argument('--via', action='append', type=_via, metavar='X,Y',
                        help='drive through these via points [m, world frame] instead of the world\'s route '
                             '(repeat; one --world)')
    parser.add_argument('--json', help='write the results here')
    parser.add_argument('--set', action='append', default=[], metavar='NAME=VALUE',
                        help='a SLAM parameter for this run (e.g. do_loop_closing=false), to compare')
    args = parser.parse_args()
    try:
        parameters = SlamParameters(**dict(_parameter(text) for text in args.set))
    except ValueError as error:
        parser.error(str(error))
    if args.via and len(args.world or ()) != 1:
        parser.error('--via takes one --world')
    if args.map_from_truth and not args.map:
        parser.error('--map-from-truth needs --map')
    try:
        results = [run(name, seed=args.seed, save_map=args.map, overlay_png=args.overlay, parameters=parameters,
                       vias=args.via, map_from_truth=args.map_from_truth)
                   for name in (args.world or sorted(ROUTES))]
    except ValueError as error:                         # a via point in a wall, or unreachable
        parser.error(str(error))
    print(f'# {platform.processor() or platform.machine()}, Python {platform.python_version()}, '
          f'numpy {np.__version__}')
    print_table(results)
    if args.json:
        Path(args.json).write_text(json.dumps({'goals': GOALS, 'results': results}, indent=2))


if __name__ == '__main__':
    main()
