"""nav2_bringup localization_launch.py end to end: the simulated TurtleBot3 in turtlebot3_world,
map_server serving turtlebot3_navigation2's map, amcl and lifecycle_manager_localization
bringing both up; an initial pose on /initialpose, and /amcl_pose and map -> base_footprint
where the robot really is."""
from __future__ import annotations

import math
import threading
from typing import Any

import numpy as np

from conftest import REPO, wait_until

MAP = REPO / 'nodes' / 'turtlebot3_navigation2' / 'map' / 'map.yaml'


def test_localization_launch_brings_up_map_server_and_amcl_and_localizes(spawn: Any) -> None:
    from zros.context import Context
    from zros.executors import MultiThreadedExecutor
    from zros.lifecycle import LifecycleClient
    from zros.node import Node
    from zros.qos import DurabilityPolicy, QoSProfile
    from zros.tf2_ros import Buffer, TransformListener
    from zros.time import Time
    from interfaces.geometry_msgs.msg import PoseWithCovarianceStamped, Twist
    from interfaces.nav_msgs.msg import Odometry

    sim = spawn.launch('turtlebot3_gazebo', 'turtlebot3_world.launch.yaml', 'real_time_factor:=4.0')
    localization = spawn.launch('nav2_bringup', 'localization_launch.py', f'map:={MAP}',
                             'use_sim_time:=True')
    ctx = Context().init([], install_signal_handlers=False)
    try:
        node = Node('localization_check', context=ctx)
        poses: list[Any] = []
        truth: list[tuple[float, float, float]] = []
        node.create_subscription(PoseWithCovarianceStamped, 'amcl_pose', poses.append,
                                 QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))
        node.create_subscription(Odometry, 'sim/ground_truth', lambda m: truth.append(
            (m.pose.pose.position.x, m.pose.pose.position.y, 2 * math.atan2(m.pose.pose.orientation.z,
                                                                            m.pose.pose.orientation.w))), 10)
        initialpose = node.create_publisher(PoseWithCovarianceStamped, 'initialpose', 10)
        cmd_vel = node.create_publisher(Twist, 'cmd_vel', 10)
        buffer = Buffer()
        TransformListener(buffer, node)
        executor = MultiThreadedExecutor(context=ctx)
        executor.add_node(node)
        threading.Thread(target=_spin, args=(executor,), daemon=True).start()

        localization.wait_for_output('Managed nodes are active', 90)
        wait_until(lambda: '/amcl/get_state' in dict(node.get_service_names_and_types()), 30)
        assert LifecycleClient(node, 'amcl').get_state(timeout_sec=10).label == 'active'
        localization.wait_for_output('No initial pose yet', 30)
        wait_until(lambda: initialpose.get_subscription_count() > 0, 20)
        msg = PoseWithCovarianceStamped()
        msg.header.frame_id = 'map'
        msg.pose.pose.position.x, msg.pose.pose.position.y = -1.7, -0.8          # the robot is at (-2, -0.5)
        msg.pose.pose.orientation.z, msg.pose.pose.orientation.w = math.sin(0.2), math.cos(0.2)
        c = np.zeros(36)
        c[0], c[7], c[35] = 0.25, 0.25, 0.07
        msg.pose.covariance = c
        initialpose.publish(msg)
        wait_until(lambda: poses, 30, message='an amcl_pose')
        # As a user does after "2D Pose Estimate": turn the robot on the spot, so amcl updates
        # (update_min_a) and converges; one update from 0.4 m off may still be 0.2 m off.
        turn = Twist()
        turn.angular.z = 0.8
        node.create_timer(0.1, lambda: cmd_vel.publish(turn))

        def error() -> float:
            x, y, _ = truth[-1]
            return math.hypot(poses[-1].pose.pose.position.x - x, poses[-1].pose.pose.position.y - y)
        wait_until(lambda: error() < 0.15, 60, message=lambda: f'amcl_pose within 0.15 m: {error():.2f} m off')

        def tf_error() -> float:   # what TF users see agrees too (each filter update moves it a little)
            t = buffer.lookup_transform('map', 'base_footprint', Time(), timeout=10.0)
            x, y, _ = truth[-1]
            return math.hypot(t.transform.translation.x - x, t.transform.translation.y - y)
        wait_until(lambda: tf_error() < 0.15, 30, message=lambda: f'map -> base_footprint within 0.15 m: '
                                                              f'{tf_error():.2f} m off')
        executor.shutdown(timeout_sec=2)
    finally:
        ctx.shutdown()
    assert 'Traceback' not in localization.output() + sim.output()


def _spin(executor: Any) -> None:
    try:
        executor.spin()
    except Exception:  # noqa: BLE001 - ends with the context
        pass
