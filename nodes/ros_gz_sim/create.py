"""create: put a robot into the running Gazebo Sim world, as ros_gz_sim's `create` does.

    zros run ros_gz_sim create -name turtlebot3_waffle -string "$(xacro gz_waffle.sdf.xacro)" -x -2 -y -0.5
    zros run ros_gz_sim create -world default -file model.sdf -name bot -Y 1.57
    zros run ros_gz_sim create -topic robot_description -name bot
    zros run ros_gz_sim create --ros-args -p name:=bot -p file:=model.sdf -p x:=1.0   # the parameter form

The model (an SDF `<model>`, or a URDF) comes from `-file` (a file, a model folder, or
`model://NAME` on the model path), `-string`, `-topic` (a latched std_msgs/String, as
robot_state_publisher's `robot_description`) or `-param` (a parameter of this node); the same
as ROS parameters `file`, `string`, `topic`, `name`, `world`, `x` ... (a parameter that is set
wins, as in ros_gz_sim). It goes to the world's `/world/<world>/create` service on the Gazebo
side (zros.sim.gz_topics); without `-world`, the world is the one `gz sim` runs (found in the
graph, waiting up to 60 s for it). The simulator reads the model's gz-sim plugins and sensors
(zros.sim.model_file). Exits 1 with one line when something is missing or the world refuses.
"""
from __future__ import annotations

import argparse
import re
import sys
import time
from pathlib import Path

import zros
from zros.arguments import NodeArgumentParser, remove_ros_args
from zros.errors import CliError
from zros.node import Node
from zros.sim.gz_topics import GZ_PREFIX
from zros.sim.sdf import default_model_path, find_model, model_sdf_file

from interfaces.gazebo_msgs.srv import SpawnEntity

from nodes.gazebo_ros.spawn_entity import _from_topic, _read_file, initial_pose

__all__ = ['main', 'parse_arguments', 'world_names']

WORLD_TIMEOUT = 60.0     # [s] to wait for a world when none is named
_SERVICE = re.compile(re.escape(GZ_PREFIX) + r'/world/([^/]+)/create$')


def parse_arguments(argv: list[str]) -> argparse.Namespace:
    """ros_gz_sim create's flags (single-dash long names, as upstream's)."""
    parser = NodeArgumentParser(prog='create', description='Spawn an entity in the Gazebo Sim world')
    for flag, text in (('-world', 'world name (default: the running one)'), ('-file', 'load the model from a file'),
                       ('-param', 'load the model from a ROS parameter'), ('-string', 'load the model from a string'),
                       ('-topic', 'load the model from a std_msgs/String topic'), ('-name', 'name of the entity')):
        parser.add_argument(flag, default='', help=text)
    parser.add_argument('-allow_renaming', nargs='?', const='true', default='false', help='(accepted)')
    for axis in ('x', 'y', 'z', 'R', 'P', 'Y'):
        parser.add_argument(f'-{axis}', type=float, default=0.0, help=f'initial {axis}')
    return parser.parse_args(argv)


def world_names(service_names: list[str]) -> list[str]:
    """The worlds whose create service is among `service_names` (the graph's)."""
    return [m.group(1) for m in map(_SERVICE.match, service_names) if m]


def _apply_parameters(node: Node, options: argparse.Namespace) -> None:
    """ros_gz_sim's ROS parameters: each one that is set replaces its flag."""
    for name in ('world', 'file', 'string', 'topic', 'name'):
        value = node.declare_parameter(name, '').value
        if value:
            setattr(options, name, str(value))
    for axis in ('x', 'y', 'z', 'R', 'P', 'Y'):
        value = node.declare_parameter(axis, 0.0).value
        if value:
            setattr(options, axis, float(value))


def _model_xml(node: Node, options: argparse.Namespace) -> str:
    if options.file:
        if options.file.startswith('model://'):
            folder = find_model(options.file.removeprefix('model://').strip('/'), default_model_path())
            if folder is None:
                raise CliError(f"model '{options.file}' not found on the model path (GZ_SIM_RESOURCE_PATH, "
                               "GAZEBO_MODEL_PATH, packages' models/)")
            return _read_file(str(model_sdf_file(folder)))
        path = Path(options.file)
        return _read_file(str(model_sdf_file(path) if path.is_dir() else path))
    if options.string:
        return options.string
    if options.topic:
        return _from_topic(node, options.topic, WORLD_TIMEOUT)
    if options.param:
        value = node.declare_parameter(options.param, '').value
        if not value:
            raise CliError(f'Failed to get XML from param [{options.param}]')
        return str(value)
    raise CliError('Must specify either -file, -param, -string or -topic')


def _world(node: Node, named: str) -> str:
    if named:
        return named
    node.get_logger().info('Requesting list of world names.')
    deadline = time.monotonic() + WORLD_TIMEOUT
    while time.monotonic() < deadline:
        worlds = world_names([name for name, _ in node.get_service_names_and_types()])
        if worlds:
            return worlds[0]
        time.sleep(0.2)
    raise CliError(f"no Gazebo world within {WORLD_TIMEOUT:g} s: is 'gz sim' running "
                   '(ros_gz_sim gz_sim.launch.py)?')


def main(args: list[str] | None = None) -> int:
    argv = list(sys.argv if args is None else args)
    options = parse_arguments(remove_ros_args(argv)[1:])
    with zros.init(args=argv):
        node = zros.create_node('ros_gz_sim')
        _apply_parameters(node, options)
        xml = _model_xml(node, options)
        if not xml.strip():
            raise CliError('the model XML is empty')
        service = f'{GZ_PREFIX}/world/{_world(node, options.world)}/create'
        client = node.create_client(SpawnEntity, service)
        if not client.wait_for_service(timeout_sec=WORLD_TIMEOUT):
            raise CliError(f"world service {service.removeprefix(GZ_PREFIX)} unavailable: is 'gz sim' running?")
        request = SpawnEntity.Request(name=options.name, xml=xml)
        (x, y, z), (qx, qy, qz, qw) = initial_pose(options)
        p, q = request.initial_pose.position, request.initial_pose.orientation
        p.x, p.y, p.z, q.x, q.y, q.z, q.w = x, y, z, qx, qy, qz, qw
        response = client.call(request, timeout_sec=WORLD_TIMEOUT)
        if response is None or not response.success:
            reason = response.status_message if response is not None else f'no answer within {WORLD_TIMEOUT:g} s'
            node.get_logger().error(f'Entity creation failed: {reason}')
            return 1
        node.get_logger().info('Entity creation successful.')
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
