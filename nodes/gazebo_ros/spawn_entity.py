"""spawn_entity.py: put a robot into the running simulator, as gazebo_ros's spawn_entity.py does.

    zros run gazebo_ros spawn_entity.py -entity burger -file models/turtlebot3_burger/model.sdf -x -2 -y -0.5
    zros run gazebo_ros spawn_entity.py -entity my_robot -topic robot_description
    zros run gazebo_ros spawn_entity.py -entity waffle -database turtlebot3_waffle -robot_namespace tb3_1

The model's XML (an SDF `model.sdf` or a URDF) comes from exactly one of `-file F`, `-topic T`
(a std_msgs/String, robot_state_publisher's `robot_description`, latched), `-database NAME` (a
model folder on GAZEBO_MODEL_PATH or in a package's `models/`) or `-stdin`, and goes to the
simulator's `/spawn_entity` (gazebo_msgs/SpawnEntity) with the pose `-x -y -z -R -P -Y` [m, rad]
and `-robot_namespace`. It waits `-timeout` seconds for the service (30), and exits 1 with one
line when something is missing or the simulator refuses. The simulator reads the model's
diff-drive plugin and sensors (zros.sim.model_file).
"""
from __future__ import annotations

import argparse
import math
import sys
import threading
import time
from pathlib import Path

import zros
from zros.arguments import NodeArgumentParser, remove_ros_args
from zros.errors import CliError
from zros.executors import SingleThreadedExecutor
from zros.node import Node
from zros.qos import DurabilityPolicy, QoSProfile
from zros.sim.sdf import default_model_path, find_model

from interfaces.gazebo_msgs.srv import SpawnEntity
from interfaces.std_msgs.msg import String

__all__ = ['main', 'parse_arguments', 'initial_pose']


def parse_arguments(argv: list[str]) -> argparse.Namespace:
    """gazebo_ros spawn_entity.py's options (single-dash long names, as upstream's)."""
    parser = NodeArgumentParser(prog='spawn_entity.py', description='Spawn an entity in the simulator')
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument('-file', help='load the model XML from a file')
    source.add_argument('-topic', help='load the model XML from a std_msgs/String topic')
    source.add_argument('-database', help='load model.sdf of a model folder on the model path')
    source.add_argument('-stdin', action='store_true', help='load the model XML from standard input')
    parser.add_argument('-entity', required=True, help='name of the entity to spawn')
    parser.add_argument('-reference_frame', default='', help="the pose's frame (empty: world)")
    parser.add_argument('-gazebo_namespace', default='', help='namespace of the simulator node')
    parser.add_argument('-robot_namespace', default='', help='namespace of the robot\'s topics')
    parser.add_argument('-timeout', type=float, default=30.0, help='seconds to wait for the service (30)')
    parser.add_argument('-unpause', action='store_true', help='(accepted)')
    parser.add_argument('-wait', help='(accepted)')
    parser.add_argument('-spawn_service_timeout', type=float, help='same as -timeout')
    parser.add_argument('-package_to_model', action='store_true', help='(accepted)')
    parser.add_argument('-b', '-bond', action='store_true', help='(accepted)')
    for axis in ('x', 'y', 'z', 'R', 'P', 'Y'):
        parser.add_argument(f'-{axis}', type=float, default=0.0, help=f'initial {axis}')
    return parser.parse_args(argv)


def initial_pose(args: argparse.Namespace) -> tuple[tuple[float, float, float], tuple[float, float, float, float]]:
    """Position and quaternion (x, y, z, w) of `-x -y -z -R -P -Y` (roll, pitch, yaw about fixed
    axes, applied in that order, as Gazebo's)."""
    cr, sr = math.cos(args.R / 2), math.sin(args.R / 2)
    cp, sp = math.cos(args.P / 2), math.sin(args.P / 2)
    cy, sy = math.cos(args.Y / 2), math.sin(args.Y / 2)
    quaternion = (sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
                  cr * cp * sy - sr * sp * cy, cr * cp * cy + sr * sp * sy)
    return (args.x, args.y, args.z), quaternion


def _read_file(path: str) -> str:
    try:
        return Path(path).read_text(encoding='utf-8')
    except (OSError, UnicodeDecodeError) as exc:
        raise CliError(f'cannot read entity XML from {path}: {exc.strerror if isinstance(exc, OSError) else exc}') from None


def _from_topic(node: Node, topic: str, timeout: float) -> str:
    """The first message on `topic` (latched, as robot_state_publisher's robot_description)."""
    received: list[str] = []
    done = threading.Event()

    def keep(msg: String) -> None:
        received.append(msg.data)
        done.set()
    qos = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    node.create_subscription(String, topic, keep, qos)
    executor = SingleThreadedExecutor(context=node.context)
    executor.add_node(node)
    deadline = time.monotonic() + timeout
    while not done.is_set() and time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.1)
    executor.remove_node(node)
    if not received:
        raise CliError(f"no message on topic '{topic}' within {timeout:g} s (is robot_state_publisher running?)")
    return received[0]


def _local_xml(args: argparse.Namespace) -> tuple[str, str]:
    """(XML, where from) for -file, -database and -stdin; read before any node starts, so a bad
    path is the command's only line."""
    if args.file:
        return _read_file(args.file), f'file {args.file}'
    if args.database:
        folder = find_model(args.database, default_model_path())
        if folder is None:
            raise CliError(f"model '{args.database}' not found on the model path (GAZEBO_MODEL_PATH and "
                           "the packages' models/ folders)")
        return _read_file(str(folder / 'model.sdf')), f'model {folder}'
    return sys.stdin.read(), 'stdin'


def main(args: list[str] | None = None) -> int:
    argv = list(sys.argv if args is None else args)
    options = parse_arguments(remove_ros_args(argv)[1:])
    timeout = options.spawn_service_timeout if options.spawn_service_timeout is not None else options.timeout
    xml, origin = _local_xml(options) if not options.topic else ('', f'topic {options.topic}')
    with zros.init(args=argv):
        node = zros.create_node('spawn_entity')
        node.get_logger().info('Spawn Entity started')
        node.get_logger().info(f'Loading entity XML from {origin}')
        if options.topic:
            xml = _from_topic(node, options.topic, timeout)
        if not xml.strip():
            raise CliError('the entity XML is empty')
        service = f"{options.gazebo_namespace.rstrip('/')}/spawn_entity"
        client = node.create_client(SpawnEntity, service)
        node.get_logger().info(f'Waiting for service {service}, timeout = {timeout:g}')
        if not client.wait_for_service(timeout_sec=timeout):
            raise CliError(f'service {service} unavailable: was the simulator (gzserver) started?')
        request = SpawnEntity.Request(name=options.entity, xml=xml, robot_namespace=options.robot_namespace,
                                      reference_frame=options.reference_frame)
        (x, y, z), (qx, qy, qz, qw) = initial_pose(options)
        p, q = request.initial_pose.position, request.initial_pose.orientation
        p.x, p.y, p.z, q.x, q.y, q.z, q.w = x, y, z, qx, qy, qz, qw
        node.get_logger().info(f'Calling service {service}')
        response = client.call(request, timeout_sec=timeout)
        if response is None:
            raise CliError(f'no answer from {service} within {timeout:g} s')
        node.get_logger().info(f'Spawn status: {response.status_message}')
        if not response.success:
            node.get_logger().error('Spawn service failed. Exiting.')
            return 1
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
