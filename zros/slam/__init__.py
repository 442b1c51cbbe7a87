"""zros.slam: online 2D SLAM as plain numpy/scipy (no Zenoh), what the slam_toolbox and
turtlebot3_cartographer nodes run.

    from zros.slam import Slam, SlamParameters, scan_points
    slam = Slam(SlamParameters(resolution=0.05))
    for odom_pose, ranges in drive():               # odometry (x, y, yaw) and LaserScan ranges
        points = scan_points(ranges, angle_min, angle_increment, range_min=0.12, range_max=3.5,
                             sensor_pose=(-0.032, 0.0, 0.0))       # the lidar in base_footprint
        update = slam.process_scan(odom_pose, points)
        update.pose, update.map_to_odom                 # the robot in the map; the TF correction
    grid = slam.occupancy_map()                         # zros.map_io.OccupancyMap: 100 / 0 / -1

Modules: `scan` (ranges to points), `grid` (log-odds map, vectorised ray casting),
`match_grid` + `matcher` (multi-resolution correlative search, Gauss-Newton refinement),
`pose_graph` (sparse least squares with loop closures), `mapper` (the pipeline),
`geometry` (SE(2) helpers), `serialization` (the saved pose graph files). The evaluation against the simulator's ground truth (ATE, map
quality) is zros.sim.evaluation, so SLAM imports nothing of the simulator. See docs/slam.md.
"""
from __future__ import annotations

from zros.slam.mapper import ScanUpdate, Slam, SlamParameters
from zros.slam.serialization import PoseGraphFileError
from zros.slam.scan import ScanPoints, scan_points

__all__ = ['Slam', 'SlamParameters', 'ScanUpdate', 'PoseGraphFileError', 'ScanPoints', 'scan_points']
