"""Robot descriptions: URDF parsing (`zros.urdf.model`) and xacro expansion (`zros.urdf.xacro`).

    from zros.urdf import load_urdf, parse_urdf
    robot = load_urdf('turtlebot3_burger.urdf')
    for link in robot.links.values(): ...          # visuals: geometry + origin + material
"""
from __future__ import annotations

from zros.urdf.model import (JOINT_TYPES, MOVING_JOINT_TYPES, Box, Collision, Cylinder, Joint, Limit, Link,
                             Material, Mesh, Mimic, Origin, Robot, Sphere, URDFError, Visual, load_urdf, parse_urdf,
                             resolve_package_uri)

__all__ = ['URDFError', 'Robot', 'Link', 'Joint', 'Visual', 'Collision', 'Origin', 'Box', 'Cylinder', 'Sphere',
           'Mesh', 'Material', 'Limit', 'Mimic', 'JOINT_TYPES', 'MOVING_JOINT_TYPES', 'parse_urdf', 'load_urdf',
           'resolve_package_uri']
