"""ParseMultiRobotPose: the robots and their poses of a multi-robot launch, from the command line
(`zros launch nav2_bringup cloned_multi_tb3_simulation_launch.py robots:="robot1={x: 1.0, y: 1.0};
robot2={x: -1.0, y: 1.0, yaw: 1.57}"`). Nav2's launch files call it while the file is read, before
launch arguments are resolved, so it reads the `robots:=` argument from the command line itself."""
from __future__ import annotations

import sys

import yaml

__all__ = ['ParseMultiRobotPose']

_POSE_KEYS = ('x', 'y', 'z', 'roll', 'pitch', 'yaw')


class ParseMultiRobotPose:
    """`ParseMultiRobotPose('robots').value()` -> {robot name: {x, y, z, roll, pitch, yaw}}.

    :param target_argument: the launch argument holding `name={yaml pose}; name={...}`.
    """

    def __init__(self, target_argument: str) -> None:
        from zros.launch.description import note_command_line_read
        prefix = target_argument + ':='
        self._text = next((arg[len(prefix):] for arg in sys.argv[1:] if arg.startswith(prefix)), '')
        note_command_line_read(target_argument)

    def value(self) -> dict[str, dict[str, float]]:
        robots: dict[str, dict[str, float]] = {}
        for item in filter(None, (part.strip() for part in self._text.split(';'))):
            name, separator, pose_text = item.partition('=')
            if not separator or not name.strip():
                continue
            pose = yaml.safe_load(pose_text) or {}
            if not isinstance(pose, dict):
                raise ValueError(f'ParseMultiRobotPose: {name.strip()}: expected a pose like {{x: 1.0, y: 2.0}}, '
                                 f'got {pose_text.strip()!r}')
            robots[name.strip()] = {key: float(pose.get(key, 0.0)) for key in _POSE_KEYS}
        return robots
