"""tf2_geometry_msgs's Python API: apply a TransformStamped to geometry_msgs messages.

    from zros.tf2_geometry_msgs import do_transform_point, do_transform_pose_stamped

`Buffer.transform()` already knows these types; this module is for code that calls the
functions directly, as ROS code does after `import tf2_geometry_msgs`.
"""
from __future__ import annotations

from zros.tf2_ros.geometry import (do_transform_point, do_transform_polygon_stamped, do_transform_pose,
                                   do_transform_pose_stamped, do_transform_pose_with_covariance_stamped,
                                   do_transform_vector3, transform_covariance)

__all__ = ['do_transform_point', 'do_transform_vector3', 'do_transform_pose', 'do_transform_pose_stamped',
           'do_transform_pose_with_covariance_stamped', 'do_transform_polygon_stamped', 'transform_covariance']
