"""Navigation benchmark: random goals driven with zros.navigation's costmap, planner and Regulated
Pure Pursuit in zros.sim, as fast as the simulation allows (no Zenoh, no processes).

    python benchmarks/navigation.py            # 20 goals per world, about 2 min
    python benchmarks/navigation.py --goals 5  # quicker

Goals (issue 18): success >= 95 %, 0 collisions, time / (shortest path length / max speed)
<= 1.5, planning time per request on the 0.05 m map < 50 ms.

What is measured, per world (turtlebot3_world, turtlebot3_house): the robot starts at the
world's spawn pose and drives to `--goals` seeded random goals in turn; each goal is a free
cell at least 0.2 m from any obstacle and reachable from where the robot is. The map is the
world's exact raster (not a SLAM-made one) and the robot's pose comes from the simulator's
ground truth (perfect localization): this measures planning and control, not mapping and
localization. A goal succeeds when the goal checker (0.25 m, 0.25 rad) accepts it within
3 x (path length / 0.22 m/s) + 30 s of simulated time. Collisions are the simulator's contact
count. The time ratio is the simulated time taken over (planned path length / 0.22 m/s); the
planned path is the planner's (smoothed) shortest path on the inflated costmap. Planning time is
wall time per request (the graph is built once per costmap, as the node does).
"""
from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from zros.navigation.controller import GoalChecker, PathFollower, ProgressChecker, RegulatedPurePursuit, RPPParams  # noqa: E402
from zros.navigation.costmap import CostmapParams, LayeredCostmap  # noqa: E402
from zros.navigation.planner import GridPlanner, PlanningError  # noqa: E402
from zros.sim import Simulation, load_world, rasterize  # noqa: E402

MAX_SPEED = 0.22          # [m/s] burger
CONTROL_PERIOD = 0.1      # [s]
CLEARANCE = 0.2           # [m] from the goal to any obstacle


def run_world(name: str, goals: int, seed: int) -> dict:
    world = load_world(name)
    raster = rasterize(world, 0.05)
    occupancy = raster.occupancy_data().reshape(raster.cells.shape)
    costmap = LayeredCostmap(CostmapParams(inflation_radius=0.55, cost_scaling_factor=3.0))
    costmap.set_static_map(occupancy, 0.05, tuple(raster.origin))
    costmap.update()
    planner = GridPlanner(costmap)
    sim = Simulation(world, seed=seed)
    robot = sim.add_robot('burger')
    follower = PathFollower(RegulatedPurePursuit(RPPParams(desired_linear_vel=MAX_SPEED, lookahead_dist=0.5,
                                                           max_angular_vel=2.0, regulated_linear_scaling_min_speed=0.1,
                                                           use_cost_regulated_linear_velocity_scaling=False)),
                            GoalChecker(), ProgressChecker())
    rng = np.random.default_rng(seed)
    rows, cols = np.nonzero(~raster.cells)
    centres = np.stack([cols, rows], axis=1) * 0.05 + np.asarray(raster.origin) + 0.025
    clear = world.distance(centres) >= CLEARANCE + 0.105
    candidates = centres[clear]
    done, ok, ratios, plan_ms = 0, 0, [], []
    while done < goals:
        gx, gy = candidates[rng.integers(len(candidates))]
        gyaw = float(rng.uniform(-math.pi, math.pi))
        pose = robot.pose
        started = time.perf_counter()
        try:
            path = planner.plan((pose.x, pose.y), (gx, gy))
        except PlanningError:
            continue                                        # not reachable: draw another goal
        plan_ms.append((time.perf_counter() - started) * 1e3)
        if math.hypot(path[-1][0] - gx, path[-1][1] - gy) > 1e-6:
            continue                                        # moved by the tolerance: not a valid goal
        length = float(np.linalg.norm(np.diff(path, axis=0), axis=1).sum())
        ideal = length / MAX_SPEED
        follower.set_path(path, gyaw)
        t0 = sim.time
        reached = False
        while sim.time - t0 < 3 * ideal + 30:
            p = robot.pose
            try:
                cmd = follower.step((p.x, p.y, p.yaw), robot.velocity[0], sim.time, costmap.cost_at)
            except Exception:  # noqa: BLE001 - FollowError: this goal failed
                break
            if cmd is None:
                reached = True
                break
            robot.command(*cmd)
            sim.step(CONTROL_PERIOD)
        robot.command(0.0, 0.0)
        done += 1
        if reached:
            ok += 1
            if ideal > 1.0:
                ratios.append((sim.time - t0) / ideal)
    return {'world': name, 'goals': done, 'success': ok / done, 'collisions': robot.collisions,
            'ratio_median': statistics.median(ratios) if ratios else math.nan,
            'ratio_max': max(ratios) if ratios else math.nan,
            'plan_ms_median': statistics.median(plan_ms), 'plan_ms_max': max(plan_ms), 'sim_time': sim.time}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--goals', type=int, default=20)
    parser.add_argument('--seed', type=int, default=1)
    args = parser.parse_args()
    rows = [run_world(name, args.goals, args.seed) for name in ('turtlebot3_world', 'turtlebot3_house')]
    print(f'| world | goals | success (goal >= 95 %) | collisions (goal 0) | time / ideal, median / max (goal <= 1.5) '
          f'| planning ms, median / max (goal < 50) | sim time [s] |')
    print('|---|---|---|---|---|---|---|')
    for r in rows:
        print(f"| {r['world']} | {r['goals']} | {100 * r['success']:.0f} % | {r['collisions']} | "
              f"{r['ratio_median']:.2f} / {r['ratio_max']:.2f} | {r['plan_ms_median']:.1f} / {r['plan_ms_max']:.1f} | "
              f"{r['sim_time']:.0f} |")
    return 0


if __name__ == '__main__':
    sys.exit(main())
