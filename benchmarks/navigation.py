"""Navigation benchmark (issue 18): goals on a SLAM-made map with AMCL, exploration, the stack's CPU.

    python benchmarks/navigation.py                    # all three parts, about 15 min
    python benchmarks/navigation.py --part goals --goals 5
    python benchmarks/navigation.py --part goals --world turtlebot3_house --per-goal   # and why each miss
    python benchmarks/navigation.py --part goals --exact-map --truth-pose   # navigation alone
    python benchmarks/navigation.py --part goals --world turtlebot3_bighouse --collision-monitor
    python benchmarks/navigation.py --part explore     # processes over Zenoh, about 3 min
    python benchmarks/navigation.py --part cpu         # processes over Zenoh at real time, 1 min
    python benchmarks/navigation.py --part load --load 4 --goals 20   # the same beside 4 busy processes

Part `goals` (in one process, no Zenoh, as fast as the simulation allows), per world
(turtlebot3_world, turtlebot3_house, turtlebot3_bighouse):
- the map is SLAM-made: benchmarks/slam.py's run (zros.slam on a scripted drive with slipping,
  miscalibrated odometry) saves it in the world frame; it is cached in --map-dir;
- the robot is localised by zros.amcl on that map with burger.yaml's amcl parameters (every
  5 Hz scan, wheel odometry from the simulator, initial pose the spawn pose as a user would
  click it), and the controller and
  planner see the pose AMCL gives, never the truth;
- the global costmap is turtlebot3_navigation2's: static layer from the SLAM map, obstacle
  layer from the scans (at the AMCL pose), inflation (0.5 m, 5.0); updated every second, when
  the path is also replanned (bt_navigator's replan_frequency 1 Hz), and the controller is
  Regulated Pure Pursuit with param/burger.yaml's FollowPath parameters;
- `--goals` seeded random goals, each a free cell >= 0.2 m from any obstacle in the true world,
  known free in the SLAM map and reachable from where the robot is, driven one after another.

A goal succeeds when the goal checker (0.25 m, 0.25 rad on AMCL's pose) accepts it within
3 x (path length / 0.22 m/s) + 30 s and the true position is within 0.35 m of the goal (the
checker's 0.25 m plus 0.1 m of localisation error); a controller failure (no progress,
collision ahead) runs bt_navigator's round of recoveries (clear the costmaps, spin, wait, back
up; up to 6) and the goal is tried again. Collisions: the simulator's
contact count. Time ratio: simulated time taken over (first planned path length / 0.22 m/s),
over goals with an ideal time above 1 s. Planning time: CPU time of each request (the first
and each replan; this thread's time, so that other programs on a shared machine do not count),
including rebuilding the search graph after a costmap update, as the planner_server does.

To tell navigation's misses from localisation's and the map's: `--truth-pose` gives the stack
the simulator's true pose instead of AMCL's, `--exact-map` the world's raster instead of the
SLAM map; `--per-goal` lists each goal not reached cleanly with the localisation error at its
end (and the worst during it), the controller's failures (and where) and each collision (where,
the command, what was running). The summary gives the localisation error (believed minus true
position at every scan) as RMS and maximum over the run.

`--collision-monitor` puts nav2_bringup's collision_monitor (nav2_params.yaml: the footprint's
approach zone, 1.2 s ahead, 6 points) between the controller and the robot, judging each command
on the robot's latest scan: it does not need the pose, so it holds when AMCL is lost (Nav2's
planner and controller cannot tell). turtlebot3_navigation2's launch does not start one (ROBOTIS's
Humble files have none), so the default run is without.

Goals (issue 18): success >= 95 %, 0 collisions, time ratio <= 1.5, planning < 50 ms per
request; exploration: >= 95 % of the reachable free area mapped within 300 s of sim time; the
whole stack's CPU at real time < 1 core; under load (issue 34): >= 95 % of goals in
turtlebot3_world with 4 busy processes beside the stack on 2 cores, no collision.
"""
from __future__ import annotations

import argparse
import contextlib
import dataclasses
import math
import os
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import yaml

REPO = Path(__file__).resolve().parents[1]
if str(REPO) not in sys.path:
    sys.path.insert(0, str(REPO))

from zros.ament_index_python.packages import get_package_share_directory  # noqa: E402
from zros.amcl import Amcl, AmclParameters, MapGrid  # noqa: E402
from zros.amcl.localizer import compose  # noqa: E402
from zros.map_io import load_map  # noqa: E402
from zros.navigation.controller import (FollowError, GoalChecker, PathFollower, ProgressChecker,  # noqa: E402
                                        RegulatedPurePursuit, RPPParams)
from zros.navigation.collision_monitor import ZONE_PARAMETERS, Decision, Zone, decide, scan_points  # noqa: E402
from zros.navigation.costmap import CostmapParams, LayeredCostmap  # noqa: E402
from zros.navigation.planner import GridPlanner, PlanningError  # noqa: E402
from zros.sim import BURGER, LDS_01, Simulation, load_world, rasterize  # noqa: E402

WORLDS = ('turtlebot3_world', 'turtlebot3_house', 'turtlebot3_bighouse')
PARAMS = REPO / 'nodes' / 'turtlebot3_navigation2' / 'param' / 'burger.yaml'
MONITOR_PARAMS = REPO / 'nodes' / 'nav2_bringup' / 'params' / 'nav2_params.yaml'
MAX_SPEED = 0.22          # [m/s] burger
CONTROL_PERIOD = 0.1      # [s] controller_frequency 10 Hz
SCAN_PERIOD = 0.2         # [s] 5 Hz lidar
REPLAN_PERIOD = 1.0       # [s] bt_navigator's replan_frequency, global costmap's update_frequency
CLEARANCE = 0.2           # [m] from the goal to any obstacle
TRUE_TOLERANCE = 0.35     # [m] goal checker's 0.25 + 0.1 localisation error
LASER = (BURGER.lidar_mount[0], BURGER.lidar_mount[1], 0.0)
NUMBER_OF_RETRIES = 6     # bt_navigator's


# -- the SLAM-made map ----------------------------------------------------------------------------
def slam_map(world: str, map_dir: Path):
    """The map benchmarks/slam.py's run makes of `world` (cached as map_dir/world.yaml)."""
    path = map_dir / f'{world}.yaml'
    if not path.exists():
        from benchmarks.slam import run as slam_run
        map_dir.mkdir(parents=True, exist_ok=True)
        print(f'{world}: making the map with zros.slam (benchmarks/slam.py) ...', file=sys.stderr, flush=True)
        slam_run(world, save_map=str(path.with_suffix('')))
    return load_map(path)


def stack_parameters() -> tuple[RPPParams, CostmapParams, AmclParameters, float]:
    """RPP, global-costmap and AMCL parameters and the controller's failure_tolerance [s] from
    turtlebot3_navigation2's burger.yaml."""
    params = yaml.safe_load(PARAMS.read_text())
    given = params['amcl']['ros__parameters']
    amcl = AmclParameters(**{f.name: type(getattr(AmclParameters, f.name))(given[f.name])
                             for f in dataclasses.fields(AmclParameters) if f.name in given})
    controller = params['controller_server']['ros__parameters']
    follow = controller['FollowPath']
    rpp = RPPParams()
    for name in RPPParams.names():
        if name in follow:
            setattr(rpp, name, type(getattr(rpp, name))(follow[name]))
    costmap = params['global_costmap']['global_costmap']['ros__parameters']
    return rpp, CostmapParams(robot_radius=costmap['robot_radius'],
                              inflation_radius=costmap['inflation_layer']['inflation_radius'],
                              cost_scaling_factor=costmap['inflation_layer']['cost_scaling_factor']), amcl, \
        float(controller.get('failure_tolerance', 0.0))


def monitor_zones(robot_radius: float) -> list[Zone]:
    """nav2_bringup's collision_monitor zones (nav2_params.yaml: one approach zone, the robot's
    footprint simulated ahead), with the footprint the local costmap publishes for a round robot
    as a circle of `robot_radius` [m]."""
    given = yaml.safe_load(MONITOR_PARAMS.read_text())['collision_monitor']['ros__parameters']
    zones = []
    for name in given['polygons']:
        zone = given[name]
        zones.append(Zone(name, zone['action_type'], radius=zone.get('radius', robot_radius),
                          **{k: zone[k] for k in ZONE_PARAMETERS if k in zone}))
    return zones


def monitor_decision(zones: list[Zone], ranges: np.ndarray, cmd: tuple[float, float]) -> Decision:
    """What the collision monitor does with `cmd` (v [m/s], w [rad/s]), judged on an LDS-01 scan's
    `ranges` [m] put in the base frame: the robot's own sensor, no localisation involved, so it
    holds when AMCL is lost."""
    points = scan_points(ranges, LDS_01.angle_min, LDS_01.angle_increment, LDS_01.range_min,
                         LDS_01.range_max) + LASER[:2]
    return decide(zones, points, np.array([cmd[0], 0.0, cmd[1]]))


# -- one world ------------------------------------------------------------------------------------
class Localised:
    """AMCL on the SLAM map fed by the simulated robot: `pose()` is what the stack believes."""

    def __init__(self, robot, grid: MapGrid, parameters: AmclParameters, seed: int, *, truth: bool = False) -> None:
        self.robot = robot
        self.truth = truth
        self.amcl = Amcl(parameters, grid, seed=seed)
        p = robot.pose
        self.amcl.set_initial_pose((p.x, p.y, p.yaw), np.diag([0.05, 0.05, 0.02]))
        self.bearings = LDS_01.angles()
        self.ranges = np.full(LDS_01.samples, np.inf)
        self.scan()

    def odom(self) -> np.ndarray:
        o = self.robot.odometry()
        return np.array([o.x, o.y, o.yaw])

    def scan(self) -> None:
        self.ranges = self.robot.scan()
        data = self.amcl.prepare_scan(self.ranges, self.bearings, LDS_01.range_min, LDS_01.range_max)
        self.amcl.update(tuple(self.odom()), data, LASER)

    def pose(self) -> tuple[float, float, float]:
        if self.truth:                                      # perfect localisation (--truth-pose)
            p = self.robot.pose
            return p.x, p.y, p.yaw
        return tuple(float(v) for v in compose(self.amcl.map_to_odom(), self.odom()))

    def error(self) -> float:
        """How far [m] the believed position is from the truth."""
        x, y, _ = self.pose()
        p = self.robot.pose
        return math.hypot(x - p.x, y - p.y)


class Stack:
    """The navigation stack around one simulated robot, stepped one control period at a time:
    AMCL and the costmap's obstacle layer take each scan, the costmap is rebuilt each second."""

    def __init__(self, world, grid, seed: int, *, truth_pose: bool = False, collision_monitor: bool = False) -> None:
        rpp, cparams, amcl, failure_tolerance = stack_parameters()
        self.monitor = monitor_zones(cparams.robot_radius) if collision_monitor else []
        self.monitor_acted = 0                  # commands the collision monitor slowed or stopped
        self.monitor_stopped = 0                # of those, the commands it stopped
        self.commands = 0                       # control periods commanded
        self.costmap = LayeredCostmap(cparams)
        self.costmap.set_static_map(grid.data, grid.resolution, tuple(grid.origin[:2]))
        self.costmap.update()
        self.planner = GridPlanner(self.costmap)
        self.sim = Simulation(world, seed=seed, on_collision=self._on_collision)
        self.robot = self.sim.add_robot('burger', odometry='encoder')   # AMCL corrects a real robot's drift
        self.loc = Localised(self.robot, MapGrid(grid.data, resolution=grid.resolution, origin=tuple(grid.origin[:2])),
                             amcl, seed, truth=truth_pose)
        self.cmd = (0.0, 0.0)
        self.doing = 'follow'                   # what the stack was doing: 'follow' or a recovery
        self.contacts: list[str] = []           # each collision: where, the command, what was running
        self.follower = PathFollower(RegulatedPurePursuit(rpp, inscribed_radius=cparams.robot_radius,
                                                          control_period=CONTROL_PERIOD),
                                     GoalChecker(), ProgressChecker(), failure_tolerance=failure_tolerance)
        self.plan_ms: list[float] = []
        self.failures: list[str] = []           # the controller's failures during the current goal
        self.worst_error = 0.0                  # the largest localisation error [m] during the current goal
        self.loc_errors: list[float] = []       # the localisation error [m] at every scan of the run
        self._next_scan = self._next_update = 0.0

    def plan(self, goal: tuple[float, float]) -> np.ndarray:
        """A path from the robot (AMCL's pose) to `goal`; the request's CPU time is recorded."""
        began = time.thread_time()
        try:
            return self.planner.plan(self.loc.pose()[:2], goal)
        finally:
            self.plan_ms.append((time.thread_time() - began) * 1e3)

    def tick(self, cmd: tuple[float, float]) -> None:
        """Command the robot for one control period, feeding sensors as their rates come due
        (through the collision monitor, with `collision_monitor`)."""
        if self.monitor:
            cmd = self.monitored(cmd)
        self.commands += 1
        self.cmd = cmd
        self.robot.command(*cmd)
        self.sim.step(CONTROL_PERIOD)
        if self.sim.time >= self._next_scan - 1e-9:
            self.loc.scan()
            x, y, yaw = self.loc.pose()
            sx, sy = x + LASER[0] * math.cos(yaw), y + LASER[0] * math.sin(yaw)
            self.costmap.add_scan((sx, sy), yaw + self.loc.bearings, self.loc.ranges, LDS_01.range_min,
                                  LDS_01.range_max)
            error = self.loc.error()
            self.loc_errors.append(error)
            self.worst_error = max(self.worst_error, error)
            self._next_scan = self.sim.time + SCAN_PERIOD
        if self.sim.time >= self._next_update - 1e-9:
            self.costmap.update()
            self.planner.invalidate()
            self._next_update = self.sim.time + REPLAN_PERIOD

    def monitored(self, cmd: tuple[float, float]) -> tuple[float, float]:
        """`cmd` as the collision monitor lets it through (counted when it slows a moving
        command, and apart when it stops one)."""
        decision = monitor_decision(self.monitor, self.loc.ranges, cmd)
        safe = float(decision.velocity[0]), float(decision.velocity[2])
        if decision.action != 'do_nothing' and any(cmd):
            self.monitor_acted += 1
            self.monitor_stopped += not any(safe)
        return safe

    def follow(self, goal: tuple[float, float, float], deadline: float) -> bool:
        """FollowPath with replanning each second until the goal checker accepts (True), the
        controller fails or the deadline passes (False)."""
        next_plan = self.sim.time + REPLAN_PERIOD
        while self.sim.time < deadline:
            if self.sim.time >= next_plan:
                try:
                    self.follower.set_path(self.plan(goal[:2]), goal[2], keep_progress=True)
                except PlanningError:
                    pass                                    # keep following the last path, as the navigator
                next_plan += REPLAN_PERIOD
            try:
                cmd = self.follower.step(self.loc.pose(), self.robot.velocity[0], self.sim.time,
                                         self.costmap.cost_at)
            except FollowError as exc:
                x, y, yaw = self.loc.pose()
                self.failures.append(f'{exc} at ({x:.2f}, {y:.2f}, {yaw:.2f})')
                return False
            if cmd is None:
                return True
            self.tick(cmd)
        return False

    def _on_collision(self, robot) -> None:
        p = robot.pose
        self.contacts.append(f'({p.x:.2f}, {p.y:.2f}) cmd ({self.cmd[0]:.2f}, {self.cmd[1]:.2f}) during {self.doing}, '
                             f'localisation error {self.loc.error():.2f} m')

    def recover(self, index: int) -> None:
        """bt_navigator's round of recoveries: clear the costmaps, spin 1.57 rad, wait 5 s, back up
        0.30 m at 0.05 m/s."""
        kind = index % 4
        self.doing = ('clear', 'spin', 'wait', 'backup')[kind]
        if kind == 0:
            self.costmap.clear()
            self.costmap.update()
            self.planner.invalidate()
        elif kind == 1:
            start = self.loc.pose()[2]
            turned, last, t0 = 0.0, start, self.sim.time
            while turned < 1.57 and self.sim.time - t0 < 10.0:
                self.tick((0.0, 1.0))
                yaw = self.loc.pose()[2]
                turned += abs(math.remainder(yaw - last, 2 * math.pi))
                last = yaw
        elif kind == 2:
            for _ in range(int(5.0 / CONTROL_PERIOD)):
                self.tick((0.0, 0.0))
        else:
            x0, y0, _ = self.loc.pose()
            t0 = self.sim.time
            while self.sim.time - t0 < 10.0 and math.hypot(self.loc.pose()[0] - x0, self.loc.pose()[1] - y0) < 0.30:
                self.tick((-0.05, 0.0))
        self.tick((0.0, 0.0))
        self.doing = 'follow'


def goal_candidates(world, grid) -> np.ndarray:
    """Cell centres free in the SLAM map and >= CLEARANCE from anything in the true world."""
    rows, cols = np.nonzero(grid.data == 0)
    centres = (np.stack([cols, rows], axis=1) + 0.5) * grid.resolution + np.asarray(grid.origin[:2])
    return centres[world.distance(centres) >= CLEARANCE + BURGER.body_radius]


def draw_goal(rng: np.random.Generator, candidates: np.ndarray, plan) -> tuple[tuple[float, float, float], np.ndarray]:
    """A seeded goal (x, y, yaw) at one of `candidates` that `plan(xy)` (a path from the robot,
    or PlanningError) reaches exactly, and that path: unreachable cells, and cells the planner's
    tolerance moves, are drawn again."""
    while True:
        gx, gy = candidates[rng.integers(len(candidates))]
        goal = (float(gx), float(gy), float(rng.uniform(-math.pi, math.pi)))
        try:
            path = plan(goal[:2])
        except PlanningError:
            continue
        if math.hypot(path[-1][0] - gx, path[-1][1] - gy) <= 1e-6:
            return goal, path


def exact_map(world):
    """The true world's raster as a map (to tell mapping errors from navigation errors)."""
    from zros.map_io import OccupancyMap
    raster = rasterize(world, 0.05)
    return OccupancyMap(raster.occupancy_data().reshape(raster.cells.shape), 0.05, (*raster.origin, 0.0))


@dataclasses.dataclass
class GoalRecord:
    """One goal's outcome, for the failure table (`--per-goal`)."""

    start: tuple[float, float]          # true position when the goal was sent [m]
    goal: tuple[float, float]
    ideal_s: float                      # first path length / 0.22 m/s
    taken_s: float
    reached: bool                       # the goal checker accepted (on the believed pose)
    true_error: float                   # [m] true position to the goal at the end
    loc_error: float                    # [m] believed minus true position at the end
    worst_loc_error: float              # [m] the largest during the goal (at scans)
    recoveries: int
    failures: list[str]                 # the controller's failures, in order
    contacts: list[str]                 # collisions during the goal

    @property
    def outcome(self) -> str:
        if self.reached and self.true_error <= TRUE_TOLERANCE:
            return 'ok'
        return 'false success' if self.reached else 'failed'


def run_goals(name: str, goals: int, seed: int, map_dir: Path | None, *, truth_pose: bool = False,
              collision_monitor: bool = False) -> dict:
    """Goals on the SLAM-made map cached in `map_dir`, or on the exact map when it is None;
    `truth_pose` gives the stack the true pose instead of AMCL's (navigation alone);
    `collision_monitor` puts nav2_bringup's collision monitor between the controller and the robot."""
    world = load_world(name)
    grid = slam_map(name, map_dir) if map_dir is not None else exact_map(world)
    stack = Stack(world, grid, seed, truth_pose=truth_pose, collision_monitor=collision_monitor)
    sim, robot = stack.sim, stack.robot
    rng = np.random.default_rng(seed)
    candidates = goal_candidates(world, grid)
    done, ok, ratios, errors, recoveries, per_goal = 0, 0, [], [], 0, []
    while done < goals:
        planned = len(stack.plan_ms)
        goal, path = draw_goal(rng, candidates, stack.plan)
        del stack.plan_ms[planned:-1]                       # the rejected draws' plans are not requests
        gx, gy = goal[:2]
        ideal = float(np.linalg.norm(np.diff(path, axis=0), axis=1).sum()) / MAX_SPEED
        stack.follower.set_path(path, goal[2])
        start, contacts0 = robot.pose, len(stack.contacts)
        stack.failures, stack.worst_error = [], stack.loc.error()
        t0 = sim.time
        deadline = t0 + 3 * ideal + 30
        reached, tries = stack.follow(goal, deadline), 0
        while not reached and sim.time < deadline and tries < NUMBER_OF_RETRIES:
            stack.recover(tries)
            tries += 1
            try:
                stack.follower.set_path(stack.plan(goal[:2]), goal[2])
            except PlanningError:
                continue
            reached = stack.follow(goal, deadline)
        robot.command(0.0, 0.0)
        done += 1
        recoveries += tries
        truth = robot.pose
        error = math.hypot(truth.x - gx, truth.y - gy)
        per_goal.append(GoalRecord((start.x, start.y), (float(gx), float(gy)), ideal, sim.time - t0, reached, error,
                                   stack.loc.error(), stack.worst_error, tries, stack.failures,
                                   stack.contacts[contacts0:]))
        if reached:
            errors.append(error)
        if reached and error <= TRUE_TOLERANCE:
            ok += 1
            if ideal > 1.0:
                ratios.append((sim.time - t0) / ideal)
    plan_ms = stack.plan_ms
    return {'world': name, 'goals': done, 'success': ok / done, 'collisions': robot.collisions,
            'recoveries': recoveries, 'monitor_acted': stack.monitor_acted, 'monitor_stopped': stack.monitor_stopped,
            'monitor': bool(stack.monitor), 'commands': stack.commands,
            'loc_rms': math.sqrt(float(np.mean(np.square(stack.loc_errors)))), 'loc_max': max(stack.loc_errors),
            'ratio_median': statistics.median(ratios) if ratios else math.nan,
            'ratio_max': max(ratios) if ratios else math.nan,
            'plan_ms_median': statistics.median(plan_ms), 'plan_ms_max': max(plan_ms),
            'error_max': max(errors) if errors else math.nan, 'sim_time': sim.time, 'per_goal': per_goal}


def print_per_goal(rows: list[dict]) -> None:
    """Every goal that was not a clean success (or touched something), with what happened."""
    for r in rows:
        print(f"\n{r['world']}: goals not reached cleanly")
        print('| # | start -> goal | outcome | true error [m] | localisation error at end / worst [m] | '
              'recoveries | controller failures | collisions |')
        print('|---|---|---|---|---|---|---|---|')
        for i, g in enumerate(r['per_goal']):
            if g.outcome == 'ok' and not g.contacts:
                continue
            failures = '-' if not g.failures else f'{len(g.failures)}x, first: {g.failures[0]}' + (
                f'; last: {g.failures[-1]}' if len(g.failures) > 1 else '')
            print(f"| {i} | ({g.start[0]:.2f}, {g.start[1]:.2f}) -> ({g.goal[0]:.2f}, {g.goal[1]:.2f}) | {g.outcome} | "
                  f"{g.true_error:.2f} | {g.loc_error:.2f} / {g.worst_loc_error:.2f} | {g.recoveries} | {failures} | "
                  f"{'; '.join(g.contacts) or '-'} |")


def print_goals(rows: list[dict]) -> None:
    print('| world | goals | success (goal >= 95 %) | collisions (goal 0) | time / ideal, median / max (goal <= 1.5) '
          '| planning ms, median / max (goal < 50) | recoveries | true error at goal, max [m] '
          '| localisation error RMS / max [m] | sim time [s] |')
    print('|---|---|---|---|---|---|---|---|---|---|')
    for r in rows:
        print(f"| {r['world']} | {r['goals']} | {100 * r['success']:.0f} % | {r['collisions']} | "
              f"{r['ratio_median']:.2f} / {r['ratio_max']:.2f} | {r['plan_ms_median']:.1f} / {r['plan_ms_max']:.1f} | "
              f"{r['recoveries']} | {r['error_max']:.2f} | {r['loc_rms']:.3f} / {r['loc_max']:.2f} | "
              f"{r['sim_time']:.0f} |")
    for r in rows:
        if r['monitor']:
            print(f"{r['world']}: the collision monitor slowed {r['monitor_acted']} commands "
                  f"(stopped {r['monitor_stopped']} of them), of {r['commands']}")


# -- processes over Zenoh (parts explore and cpu) -----------------------------------------------
CLK_TCK = os.sysconf('SC_CLK_TCK') if hasattr(os, 'sysconf') else 100


class Stackprocs:
    """The stack as a user starts it: `zros launch` processes in a private zros domain, each in
    its own process group (killed at the end); their output goes to files in a scratch folder."""

    def __init__(self) -> None:
        from zros.testing.domains import DomainLock
        self.lock = DomainLock()
        self.env = dict(os.environ, ZROS_DOMAIN_ID=str(self.lock.domain), TURTLEBOT3_MODEL='burger')
        for name in ('ZROS_CONNECT', 'ZROS_DISCOVERY', 'ZROS_CONFIG', 'ZROS_LISTEN'):
            self.env.pop(name, None)
        self.dir = Path(tempfile.mkdtemp(prefix='zros-nav-bench-'))
        self.procs: dict[str, subprocess.Popen] = {}

    def launch(self, name: str, *argv: str) -> None:
        out = open(self.dir / f'{name}.log', 'wb')
        self.procs[name] = subprocess.Popen([sys.executable, '-m', 'zros', 'launch', *argv], stdout=out,
                                            stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL, env=self.env,
                                            cwd=REPO, start_new_session=True)

    def output(self, name: str) -> str:
        return (self.dir / f'{name}.log').read_text(errors='replace')

    def wait_for_output(self, name: str, text: str, timeout: float) -> None:
        deadline = time.monotonic() + timeout
        while text not in self.output(name):
            if time.monotonic() > deadline or self.procs[name].poll() is not None:
                raise RuntimeError(f'{name}: no "{text}" within {timeout:.0f} s; its output is in {self.dir}')
            time.sleep(0.2)

    def cpu_seconds(self) -> dict[str, float]:
        """CPU time [s] so far of every live process of the stack (the launch supervisors and
        their descendants), by the command line's `pkg executable` or launch file."""
        table: dict[int, tuple[int, float, str]] = {}
        for entry in Path('/proc').iterdir():
            if not entry.name.isdigit():
                continue
            try:
                fields = (entry / 'stat').read_text().rsplit(')', 1)[1].split()
                argv = [a.decode(errors='replace') for a in (entry / 'cmdline').read_bytes().split(b'\0') if a]
            except (OSError, IndexError, ValueError):
                continue
            cpu = (int(fields[11]) + int(fields[12])) / CLK_TCK
            table[int(entry.name)] = (int(fields[1]), cpu, ' '.join(argv[4:6]) if argv[1:3] == ['-m', 'zros'] else
                                      ' '.join(argv[:2]))
        ours = {p.pid for p in self.procs.values()}
        grew = True
        while grew:
            more = {pid for pid, (ppid, _, _) in table.items() if ppid in ours} - ours
            grew = bool(more)
            ours |= more
        usage: dict[str, float] = {}
        for pid in ours & table.keys():
            _, cpu, label = table[pid]
            usage[label] = usage.get(label, 0.0) + cpu
        return usage

    def close(self) -> None:
        for proc in self.procs.values():
            with contextlib.suppress(ProcessLookupError, PermissionError):
                os.killpg(proc.pid, signal.SIGINT)
        deadline = time.monotonic() + 5.0
        for proc in self.procs.values():
            try:
                proc.wait(timeout=max(0.1, deadline - time.monotonic()))
            except subprocess.TimeoutExpired:
                with contextlib.suppress(ProcessLookupError, PermissionError):
                    os.killpg(proc.pid, signal.SIGKILL)
                proc.wait(timeout=10)
        self.lock.close()


def _spin(executor, seconds: float) -> None:
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        executor.spin_once(timeout_sec=0.05)


def reachable_free(world_name: str, resolution: float):
    """The true world's free cells connected to the spawn point (what exploration can map)."""
    from scipy import ndimage
    world = load_world(world_name)
    raster = rasterize(world, resolution)
    labels, _ = ndimage.label(~raster.cells)
    inside = labels == labels[raster.cell_of(world.spawn.x, world.spawn.y)]
    return world, raster, inside


def mapped_share(msg, world, raster, inside: np.ndarray) -> float:
    """Share of the `inside` cells that the SLAM map (frame: the spawn pose) knows, free or occupied."""
    info = msg.info
    data = np.asarray(msg.data, np.int8).reshape(info.height, info.width)
    rows, cols = np.nonzero(inside)
    x = raster.origin[0] + (cols + 0.5) * raster.resolution - world.spawn.x
    y = raster.origin[1] + (rows + 0.5) * raster.resolution - world.spawn.y
    c, s = math.cos(-world.spawn.yaw), math.sin(-world.spawn.yaw)
    mx, my = c * x - s * y, s * x + c * y
    col = np.floor((mx - info.origin.position.x) / info.resolution).astype(int)
    row = np.floor((my - info.origin.position.y) / info.resolution).astype(int)
    ok = (col >= 0) & (row >= 0) & (col < info.width) & (row < info.height)
    known = np.zeros(len(rows), bool)
    known[ok] = data[row[ok], col[ok]] >= 0
    return float(known.mean())


def run_explore(rtf: float, budget_s: float = 300.0) -> dict:
    """explore_lite on turtlebot3_world from an unknown map: gzserver at `rtf`, nav2_bringup with
    slam:=True (the slam_toolbox node and the navigation servers), explore.launch.py."""
    import zros
    from zros.executors import SingleThreadedExecutor
    from zros.node import Node
    from zros.qos import DurabilityPolicy, QoSProfile
    from interfaces.nav_msgs.msg import OccupancyGrid
    from interfaces.rosgraph_msgs.msg import Clock
    world, raster, inside = reachable_free('turtlebot3_world', 0.05)
    stack = Stackprocs()
    context = None
    try:
        stack.launch('world', 'turtlebot3_gazebo', 'turtlebot3_world.launch.yaml', f'real_time_factor:={rtf}')
        burger = os.path.join(get_package_share_directory('turtlebot3_navigation2'), 'param', 'burger.yaml')
        stack.launch('nav', 'nav2_bringup', 'bringup_launch.py', 'use_sim_time:=True', 'slam:=True',
                     f'params_file:={burger}')
        stack.wait_for_output('nav', 'Managed nodes are active', 180)
        context = zros.init(args=[], domain_id=stack.lock.domain, signal_handler_options=False)
        node = Node('navigation_benchmark')
        clock = [0.0]
        shares: list[tuple[float, float]] = []
        node.create_subscription(Clock, '/clock', lambda m: clock.__setitem__(0, m.clock.sec + m.clock.nanosec / 1e9), 10)
        node.create_subscription(OccupancyGrid, '/map',
                                 lambda m: shares.append((clock[0], mapped_share(m, world, raster, inside))),
                                 QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))
        executor = SingleThreadedExecutor()
        executor.add_node(node)
        while clock[0] == 0.0:
            _spin(executor, 0.2)
        stack.launch('explore', 'explore_lite', 'explore.launch.py', 'use_sim_time:=True')
        t0, cpu0 = clock[0], sum(stack.cpu_seconds().values())
        finished = None
        while clock[0] - t0 < budget_s:
            _spin(executor, 0.5)
            if finished is None and 'All frontiers traversed/tried out' in stack.output('explore'):
                finished = clock[0] - t0
                break
        _spin(executor, 2.0)                               # the map published after the last goal
        sim_s = clock[0] - t0
        cpu_s = sum(stack.cpu_seconds().values()) - cpu0
    finally:
        if context is not None:
            zros.shutdown()
        stack.close()
    within = [(t - t0, share) for t, share in shares if t - t0 <= budget_s]
    reached = next((t for t, share in within if share >= 0.95), None)
    return {'rtf': rtf, 'share': within[-1][1] if within else 0.0, 'time_to_95': reached, 'finished': finished,
            'sim_s': sim_s, 'cores_per_sim_s': cpu_s / sim_s if sim_s else math.nan, 'logs': str(stack.dir)}


@contextlib.contextmanager
def navigation_day(busy: int = 0):
    """The course's navigation day at real time, as a user starts it: gzserver (turtlebot3_world),
    turtlebot3_navigation2's navigation2.launch.py (map_server, AMCL, the navigation servers) and a
    BasicNavigator with AMCL's initial pose set, its stack up; `busy` processes spinning a core
    each beside it (a loaded machine). Yields (stack, navigator, pose(x, y), state), where state
    holds the sim clock ('clock' [s]) and the simulator's collision count ('collisions')."""
    import zros
    from zros.nav2_simple_commander.robot_navigator import BasicNavigator
    from zros.qos import DurabilityPolicy, QoSProfile
    from interfaces.geometry_msgs.msg import PoseStamped
    from interfaces.rosgraph_msgs.msg import Clock
    from interfaces.std_msgs.msg import UInt32
    stack = Stackprocs()
    hogs = [subprocess.Popen([sys.executable, '-c', 'while True: pass'], start_new_session=True)
            for _ in range(busy)]
    context = None
    try:
        stack.launch('world', 'turtlebot3_gazebo', 'turtlebot3_world.launch.yaml', 'real_time_factor:=1.0')
        stack.launch('nav', 'turtlebot3_navigation2', 'navigation2.launch.py', 'use_sim_time:=True', 'rviz:=false')
        context = zros.init(args=[], domain_id=stack.lock.domain, signal_handler_options=False)
        navigator = BasicNavigator()
        state = {'clock': 0.0, 'collisions': 0}

        def pose(x: float, y: float) -> PoseStamped:
            p = PoseStamped()
            p.header.frame_id = 'map'
            p.header.stamp = navigator.get_clock().now().to_msg()
            p.pose.position.x, p.pose.position.y = x, y
            p.pose.orientation.w = 1.0
            return p
        navigator.create_subscription(Clock, '/clock',
                                      lambda m: state.__setitem__('clock', m.clock.sec + m.clock.nanosec / 1e9), 10)
        navigator.create_subscription(UInt32, 'sim/collisions', lambda m: state.__setitem__('collisions', m.data),
                                      QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))
        navigator.setInitialPose(pose(-2.0, -0.5))
        navigator.waitUntilNav2Active()
        yield stack, navigator, pose, state
        navigator.cancelTask()
        navigator.destroy_node()
    finally:
        if context is not None:
            zros.shutdown()
        stack.close()
        for hog in hogs:
            hog.kill()
            hog.wait(timeout=10)


#: Goals of the real-time parts: across turtlebot3_world's pillars and back, in the map frame.
ROUTE = [(-0.55, 0.55), (0.55, -0.55), (1.65, 1.65), (-1.65, -1.65)]


def run_cpu(seconds: float) -> dict:
    """The navigation day at real time, BasicNavigator driving goal after goal; the CPU of every
    process of the stack over `seconds` of wall time."""
    with navigation_day() as (stack, navigator, pose, state):
        cpu0, wall0, sim0 = stack.cpu_seconds(), time.monotonic(), state['clock']
        goals = 0
        while time.monotonic() - wall0 < seconds:
            navigator.goToPose(pose(*ROUTE[goals % len(ROUTE)]))
            while not navigator.isTaskComplete() and time.monotonic() - wall0 < seconds:
                pass
            goals += 1
        cpu1, wall, sim_s = stack.cpu_seconds(), time.monotonic() - wall0, state['clock'] - sim0
    per = {name: (cpu1[name] - cpu0.get(name, 0.0)) / wall for name in cpu1}
    return {'cores': sum(per.values()), 'per_process': sorted(per.items(), key=lambda kv: -kv[1]), 'goals': goals,
            'wall_s': wall, 'rtf': sim_s / wall}


def run_load(busy: int, goals: int, goal_timeout_s: float = 120.0) -> dict:
    """The navigation day with `busy` processes spinning beside the stack: `goals` goals along
    ROUTE, each given `goal_timeout_s` of wall time; how many succeeded, the collisions, and what
    the stack said about the load (missed control rates, failed lifecycle steps)."""
    from zros.nav2_simple_commander.robot_navigator import TaskResult
    outcomes: list[str] = []
    with navigation_day(busy) as (stack, navigator, pose, state):
        wall0, sim0, load0 = time.monotonic(), state['clock'], os.getloadavg()[0]
        for index in range(goals):
            navigator.goToPose(pose(*ROUTE[index % len(ROUTE)]))
            deadline = time.monotonic() + goal_timeout_s
            while not navigator.isTaskComplete() and time.monotonic() < deadline:
                pass
            if not navigator.isTaskComplete():
                navigator.cancelTask()
                outcomes.append('timed out')
                continue
            result = navigator.getResult()
            outcomes.append('succeeded' if result == TaskResult.SUCCEEDED else str(result).split('.')[-1].lower())
        wall, sim_s, load1 = time.monotonic() - wall0, state['clock'] - sim0, os.getloadavg()[0]
        log = stack.output('nav')
        collisions = state['collisions']
    return {'busy': busy, 'goals': goals, 'success': outcomes.count('succeeded') / goals, 'outcomes': outcomes,
            'collisions': collisions, 'missed_rate_warnings': log.count('Control loop missed its desired rate'),
            'failed_transitions': log.count('Failed to change state'), 'rtf': sim_s / wall if wall else math.nan,
            'load': (load0 + load1) / 2, 'logs': str(stack.dir)}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--part', choices=('goals', 'explore', 'cpu', 'load', 'all'), default='all')
    parser.add_argument('--goals', type=int, default=20)
    parser.add_argument('--seed', type=int, default=1)
    parser.add_argument('--world', action='append', choices=WORLDS, help='default: both (goals part)')
    parser.add_argument('--map-dir', type=Path, default=Path('/tmp/zros-navigation-benchmark'),
                        help='where the SLAM-made maps are cached')
    parser.add_argument('--exact-map', action='store_true',
                        help="goals on the world's exact raster instead of the SLAM-made map (AMCL still localises)")
    parser.add_argument('--truth-pose', action='store_true',
                        help="the stack sees the simulator's true pose instead of AMCL's (navigation alone)")
    parser.add_argument('--collision-monitor', action='store_true',
                        help="nav2_bringup's collision_monitor between the controller and the robot")
    parser.add_argument('--per-goal', action='store_true', help='also list each goal not reached cleanly, and why')
    parser.add_argument('--rtf', type=float, default=2.0, help='real-time factor of the exploration run')
    parser.add_argument('--seconds', type=float, default=60.0, help='wall seconds of the real-time CPU run')
    parser.add_argument('--load', type=int, default=4, help='busy processes beside the stack (part load)')
    args = parser.parse_args()
    if args.part in ('goals', 'all'):
        map_dir = None if args.exact_map else args.map_dir
        rows = [run_goals(name, args.goals, args.seed, map_dir, truth_pose=args.truth_pose,
                          collision_monitor=args.collision_monitor)
                for name in (args.world or WORLDS)]
        print_goals(rows)
        if args.per_goal:
            print_per_goal(rows)
    if args.part in ('explore', 'all'):
        r = run_explore(args.rtf)
        to95 = f"{r['time_to_95']:.0f} s" if r['time_to_95'] is not None else 'not reached'
        done = f"{r['finished']:.0f} s" if r['finished'] is not None else 'not within 300 s'
        print(f"\n| exploration, turtlebot3_world (sim at {r['rtf']:g}x) | value | goal |\n|---|---|---|\n"
              f"| reachable free area mapped after {min(r['sim_s'], 300.0):.0f} s of sim time | {100 * r['share']:.1f} % | >= 95 % |\n"
              f"| sim time until 95 % mapped | {to95} | <= 300 s |\n"
              f"| sim time until explore_lite stopped (no frontier left) | {done} | |\n"
              f"| CPU of the whole stack per sim second (sim, SLAM, navigation, explore) | {r['cores_per_sim_s']:.2f} cores | < 1 |")
        print(f"(logs: {r['logs']})")
    if args.part in ('cpu', 'all'):
        r = run_cpu(args.seconds)
        top = ', '.join(f'{name.split()[-1]} {cores:.2f}' for name, cores in r['per_process'][:5])
        print(f"\n| whole stack at real time (gzserver, map_server, AMCL, navigation; {r['goals']} goals in "
              f"{r['wall_s']:.0f} s, sim ran at {r['rtf']:.2f}x) | value | goal |\n|---|---|---|\n"
              f"| CPU | {r['cores']:.2f} cores | < 1 |\n(largest: {top})")
    if args.part == 'load':
        r = run_load(args.load, args.goals)
        print(f"\n| navigation at real time with {r['busy']} busy processes beside it ({os.cpu_count()} CPUs, "
              f"load average {r['load']:.1f}, sim ran at {r['rtf']:.2f}x) | value | goal |\n|---|---|---|\n"
              f"| goals reached | {100 * r['success']:.0f} % of {r['goals']} | >= 95 % |\n"
              f"| collisions | {r['collisions']} | 0 |\n"
              f"| 'Control loop missed its desired rate' warnings | {r['missed_rate_warnings']} | (information) |\n"
              f"| failed lifecycle transitions | {r['failed_transitions']} | 0 |")
        print(f"(outcomes: {', '.join(r['outcomes'])}; logs: {r['logs']})")
    return 0


if __name__ == '__main__':
    sys.exit(main())
