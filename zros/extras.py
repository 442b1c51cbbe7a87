"""The optional dependencies, by extra, and the one-line error when one is missing.

`pip install zros` installs the middleware (nodes, topics, services, actions, parameters,
launch, the CLI); the robot half and the tools come as extras (pyproject.toml), so a program
that reaches for one that is not installed gets a line that says which to install, rather
than a ModuleNotFoundError traceback from deep inside a node.
"""
from __future__ import annotations

from zros.errors import ZrosError

__all__ = ['EXTRA_OF', 'MissingExtraError', 'missing_extra']

#: The import name of each optional package -> the extra that installs it.
EXTRA_OF = {
    'scipy': 'nav',           # SLAM, AMCL, costmaps and planners (the simulator's extra has it too)
    'pymunk': 'sim',          # the simulator's and turtlesim's physics
    'trimesh': 'sim',         # mesh collisions in Gazebo worlds, meshes in the view
    'collada': 'sim',
    'xacro': 'sim',           # robot descriptions
    'viser': 'view',
    'websockets': 'view',     # the view's server; rosbridge's too (its 'bridge' extra has it)
    'cbor2': 'bridge',        # rosbridge's CBOR frames
    'foxglove': 'bridge',     # foxglove_bridge's server (foxglove-sdk)
    'mcap': 'bag',
    'mcap_ros2': 'bag',
    'rosbags': 'bag',
    'cryptography': 'security',
}


class MissingExtraError(ZrosError, ImportError):
    """An optional package is not installed; the text names the extra that installs it."""


def missing_extra(exc: ImportError, what: str) -> MissingExtraError | None:
    """The one-line error for `exc` when it is an extra's package that is missing, else None.

    Args:
        exc: the ImportError raised while importing or running `what`.
        what: what needed it, as the user typed it (`zros view`, `turtlesim turtlesim_node`).
    """
    extra = EXTRA_OF.get((getattr(exc, 'name', None) or '').split('.')[0])
    if extra is None:
        return None
    return MissingExtraError(f"{what} needs the '{extra}' extra: pip install 'zros[{extra}]'")
