"""zros.amcl: Adaptive Monte Carlo Localization on a known map, as nav2_amcl does it, in numpy.

The filter is plain code with no Zenoh, split the way nav2_amcl splits it (pf/, motion_model/,
sensors/laser/), so it is tested and benchmarked on its own; the `nav2_amcl amcl` node only
wires topics, parameters and TF to `Amcl`:

    from zros.amcl import Amcl, AmclParameters, MapGrid
    amcl = Amcl(AmclParameters(), MapGrid(data, resolution=0.05, origin=(-10.0, -10.0)), seed=1)
    amcl.set_initial_pose((x, y, yaw), covariance)        # or amcl.global_localization()
    result = amcl.update(odom_pose, scan, laser_pose)     # each scan, with odom -> base at its time
    if result.published: result.pose, result.covariance, amcl.map_to_odom(odom_pose)

Everything is vectorised over particles and beams (no Python loop per particle, beam or cell).
See docs/localization.md for the behaviour and where it differs from Nav2.
"""
from __future__ import annotations

from zros.amcl.localizer import Amcl, AmclParameters, LaserScanData, UpdateResult
from zros.amcl.map_grid import MapGrid
from zros.amcl.motion_models import (DifferentialMotionModel, MotionModel, OmniMotionModel, create_motion_model,
                                     MOTION_MODELS)
from zros.amcl.particle_filter import ParticleFilter, PoseEstimate
from zros.amcl.sensor_models import LikelihoodFieldModel, LikelihoodFieldProbModel, create_laser_model

__all__ = ['Amcl', 'AmclParameters', 'LaserScanData', 'UpdateResult', 'MapGrid', 'MotionModel',
           'DifferentialMotionModel', 'OmniMotionModel', 'create_motion_model', 'MOTION_MODELS',
           'ParticleFilter', 'PoseEstimate', 'LikelihoodFieldModel', 'LikelihoodFieldProbModel',
           'create_laser_model']
