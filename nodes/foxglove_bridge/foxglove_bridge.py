"""foxglove_bridge: Foxglove (and any Foxglove WebSocket client) sees and drives the zros graph.

    zros run foxglove_bridge foxglove_bridge
    zros run foxglove_bridge foxglove_bridge --ros-args -p port:=8766 -p "topic_whitelist:=['/scan', '/tf.*']"
    zros launch foxglove_bridge foxglove_bridge_launch.xml port:=8765

Then open Foxglove and connect to ws://localhost:8765. The node only reads ROS's
foxglove_bridge parameters (same names and defaults) into a BridgeConfig; the bridge itself is
zros.bridges.foxglove. A bad parameter or a port in use is one error line and exit 1.
"""
from __future__ import annotations

import sys

import zros
from zros.bridges.foxglove import CAPABILITIES, BridgeConfig, FoxgloveBridge
from zros.executors import ExternalShutdownException
from zros.node import Node

__all__ = ['main', 'read_config']

_DEFAULTS = BridgeConfig()


def read_config(node: Node) -> BridgeConfig:
    """Declare foxglove_bridge's parameters on `node` and return their values."""
    def declare(name: str, default):
        value = node.declare_parameter(name, list(default) if isinstance(default, tuple) else default).value
        return tuple(value) if isinstance(default, tuple) else value
    return BridgeConfig(
        port=declare('port', _DEFAULTS.port),
        address=declare('address', _DEFAULTS.address),
        topic_whitelist=declare('topic_whitelist', _DEFAULTS.topic_whitelist),
        param_whitelist=declare('param_whitelist', _DEFAULTS.param_whitelist),
        service_whitelist=declare('service_whitelist', _DEFAULTS.service_whitelist),
        client_topic_whitelist=declare('client_topic_whitelist', _DEFAULTS.client_topic_whitelist),
        send_buffer_limit=declare('send_buffer_limit', _DEFAULTS.send_buffer_limit),
        message_backlog_size=declare('message_backlog_size', _DEFAULTS.message_backlog_size),
        capabilities=declare('capabilities', CAPABILITIES),
        include_hidden=declare('include_hidden', _DEFAULTS.include_hidden),
        min_qos_depth=declare('min_qos_depth', _DEFAULTS.min_qos_depth),
        max_qos_depth=declare('max_qos_depth', _DEFAULTS.max_qos_depth),
        use_sim_time=node.get_parameter('use_sim_time').value)


def main(args=None) -> int:
    try:
        with zros.init(args=args):
            node = Node('foxglove_bridge')
            try:
                config = read_config(node)
                bridge = FoxgloveBridge(node, config)
            except ModuleNotFoundError as exc:
                print(f"foxglove_bridge: the '{exc.name}' package is missing: pip install 'zros[bridge]'",
                      file=sys.stderr)
                return 1
            except (ValueError, TypeError, RuntimeError, OSError) as exc:
                print(f'foxglove_bridge: {exc}', file=sys.stderr)
                return 1
            node.get_logger().info(f'Foxglove WebSocket server listening on '
                                   f'ws://{config.address}:{bridge.port}')
            try:
                zros.spin(node)
            finally:
                bridge.close()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
