"""Saving the map that arrives on a topic: what map_saver_cli and map_saver_server share."""
from __future__ import annotations

import threading
from typing import Any

from zros.callback_groups import ReentrantCallbackGroup
from zros.map_io import MapFileError, map_from_msg, save_map
from zros.node import Node
from zros.qos import DurabilityPolicy, QoSProfile

from interfaces.nav_msgs.msg import OccupancyGrid

__all__ = ['save_map_from_topic', 'DEFAULT_TIMEOUT']

#: [s] to wait for the map (nav2 waits 2 s, too short for a map published every few seconds).
DEFAULT_TIMEOUT = 5.0


def save_map_from_topic(node: Node, topic: str, name: str, *, timeout: float = DEFAULT_TIMEOUT,
                        transient_local: bool = True, **save_options: Any) -> bool:
    """Wait up to `timeout` [s] (wall time) for one map on `topic`, write it with
    zros.map_io.save_map(name, **save_options), and log each step as nav2's map_saver does.
    The node must be spinning on an executor with a free thread (the subscription uses a
    reentrant group, so a service callback of the same node may call this). Returns whether the
    map was saved."""
    logger = node.get_logger()
    logger.info(f"Saving map from '{topic}' topic to '{name}' file")
    durability = DurabilityPolicy.TRANSIENT_LOCAL if transient_local else DurabilityPolicy.VOLATILE
    received: list[Any] = []
    arrived = threading.Event()

    def keep(msg: Any) -> None:
        received.append(msg)
        arrived.set()
    subscription = node.create_subscription(OccupancyGrid, topic, keep, QoSProfile(depth=1, durability=durability),
                                            callback_group=ReentrantCallbackGroup())
    try:
        arrived.wait(timeout)
    finally:
        node.destroy_subscription(subscription)
    if not received:
        qos = 'reliable, transient local' if transient_local else 'reliable, volatile'
        logger.error(f"Failed to save the map: no map on '{node.resolve_topic_name(topic)}' within {timeout:g} s "
                     f'(subscribed {qos}; is SLAM or map_server running?)')
        return False
    msg = received[-1]
    logger.info(f'Received a {msg.info.width} X {msg.info.height} map @ {msg.info.resolution:.3f} m/pix')
    try:
        yaml_path, image_path = save_map(map_from_msg(msg), name, **save_options)
    except (MapFileError, ValueError) as exc:
        logger.error(f'Failed to save the map: {exc}')
        return False
    logger.info(f'Writing map occupancy data to {image_path}')
    logger.info(f'Writing map metadata to {yaml_path}')
    logger.info('Map saved')
    return True
