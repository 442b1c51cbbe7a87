"""zros.sim: a 2D TurtleBot3 simulator in Gazebo's role, as a plain library (no Zenoh).

The `turtlebot3_gazebo gzserver` node wraps it; benchmarks and tests use it directly:

    from zros.sim import Simulation, load_world, rasterize
    world = load_world('turtlebot3_world')          # or the path of your own world file
    sim = Simulation(world, seed=1)                 # fixed 5 ms steps, seeded noise
    robot = sim.add_robot('burger', (-2.0, -0.5, 0.0))
    robot.command(0.2, 0.3)                         # linear [m/s], angular [rad/s]; holds
    sim.step(2.0)                                   # advance 2 s of simulated time
    robot.pose                                      # ground truth Pose2D(x, y, yaw)
    robot.odometry()                                # wheel-encoder odometry (drifts)
    robot.scan()                                    # 360 lidar ranges, float32
    rasterize(world, 0.05).cells                    # exact ground-truth occupancy (bool grid)

zros.sim.evaluation scores a SLAM run against that truth. See docs/robot.md for the models,
worlds, numbers and what differs from Gazebo.
"""
from __future__ import annotations

from zros.rotations import wrap_angle
from zros.sim.raster import OccupancyRaster, rasterize
from zros.sim.robot import BURGER, TURTLEBOT4, WAFFLE, WAFFLE_PI, RobotSpec, robot_spec
from zros.sim.sensors import LDS_01, TURTLEBOT3_IMU, ImuReading, ImuSpec, LidarSpec
from zros.sim.simulation import DEFAULT_DT, OdometryState, SimError, SimRobot, Simulation
from zros.sim.world import Pose2D, World
from zros.sim.world_file import WORLDS_DIR, WorldFileError, load_world, parse_world, world_names, world_path

__all__ = [
    'Simulation', 'SimRobot', 'SimError', 'OdometryState', 'DEFAULT_DT',
    'World', 'Pose2D', 'load_world', 'parse_world', 'world_names', 'world_path', 'WORLDS_DIR',
    'WorldFileError', 'OccupancyRaster', 'rasterize',
    'RobotSpec', 'BURGER', 'WAFFLE', 'WAFFLE_PI', 'TURTLEBOT4', 'robot_spec', 'wrap_angle',
    'LidarSpec', 'LDS_01', 'ImuSpec', 'TURTLEBOT3_IMU', 'ImuReading',
]
