"""zros: ROS 2's programming model (rclpy's API) on Eclipse Zenoh, in plain Python.

    import zros
    from zros.node import Node
    from interfaces.std_msgs.msg import String
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any

from zros.context import Context, get_default_context
from zros.signals import SignalHandlerOptions, install_signal_handlers, uninstall_signal_handlers

if TYPE_CHECKING:
    from zros.parameter import Parameter
    from zros.executors import Executor
    from zros.node import Node
    from zros.task import Future

__all__ = ['init', 'ok', 'shutdown', 'try_shutdown', 'spin', 'spin_once', 'spin_until_future_complete',
           'create_node', 'get_global_executor', 'get_default_context', 'Context', 'Parameter', 'utilities',
           'SignalHandlerOptions', 'install_signal_handlers', 'uninstall_signal_handlers']

__version__ = '0.1.0'

_global_executor = None


def init(args: list[str] | None = None, *, context: Context | None = None, domain_id: int | None = None,
         signal_handler_options: SignalHandlerOptions | bool | None = None) -> Context:
    """Connect this process to the zros system; usable plain or as `with zros.init():`.

    As rclpy, SIGINT and SIGTERM handlers are installed (zros.signals) when initializing the
    default context, unless `signal_handler_options` says otherwise (SignalHandlerOptions.NO,
    or False, to keep the program's own)."""
    ctx = context or get_default_context()
    if signal_handler_options is None:
        signal_handler_options = ctx is get_default_context()
    return ctx.init(args, domain_id=domain_id, install_signal_handlers=signal_handler_options)


def ok(*, context: Context | None = None) -> bool:
    return (context or get_default_context()).ok()


def shutdown(*, context: Context | None = None, uninstall_handlers: bool | None = None) -> None:
    """Shut the context down. Signal handlers are uninstalled with the default context unless
    `uninstall_handlers` is False.

    Raises:
        RuntimeError: The context is not initialized, or was shut down already (as rclpy; after a
            signal shut it down the call is harmless). `try_shutdown` never raises.
    """
    ctx = context or get_default_context()
    ctx.check_can_shut_down()
    try_shutdown(context=ctx, uninstall_handlers=uninstall_handlers)


def try_shutdown(*, context: Context | None = None, uninstall_handlers: bool | None = None) -> None:
    """Shut the context down if it is up; a context already shut down is left as it is."""
    global _global_executor
    ctx = context or get_default_context()
    if _global_executor is not None and (context is None or _global_executor.context is ctx):
        _global_executor.shutdown()
        _global_executor = None
    ctx.shutdown()
    if uninstall_handlers or (uninstall_handlers is None and ctx is get_default_context()):
        uninstall_signal_handlers()


def create_node(node_name: str, **kwargs: Any) -> 'Node':
    from zros.node import Node
    return Node(node_name, **kwargs)


def get_global_executor() -> 'Executor':
    global _global_executor
    if _global_executor is None or _global_executor._is_shutdown:
        from zros.executors import SingleThreadedExecutor
        _global_executor = SingleThreadedExecutor()
    return _global_executor


def spin(node: 'Node', executor: 'Executor | None' = None) -> None:
    """Run `node`'s callbacks until shutdown (Ctrl-C raises KeyboardInterrupt, as in rclpy)."""
    executor = executor or get_global_executor()
    try:
        executor.add_node(node)
        executor.spin()
    finally:
        executor.remove_node(node)


def spin_once(node: 'Node', *, executor: 'Executor | None' = None, timeout_sec: float | None = None) -> None:
    executor = executor or get_global_executor()
    try:
        executor.add_node(node)
        executor.spin_once(timeout_sec=timeout_sec)
    finally:
        executor.remove_node(node)


def spin_until_future_complete(node: 'Node', future: 'Future', executor: 'Executor | None' = None,
                               timeout_sec: float | None = None) -> None:
    executor = executor or get_global_executor()
    try:
        executor.add_node(node)
        executor.spin_until_future_complete(future, timeout_sec)
    finally:
        executor.remove_node(node)


def __getattr__(name: str) -> Any:
    """`rclpy.clock`, `rclpy.executors` ... after a bare `import rclpy`: in rclpy they are there
    because `rclpy.node` imported them; code (tf2_ros's tests among it) reaches them that way.
    Imported on first use, so `import zros` stays light (`zros.Parameter` too: the message
    codec it needs brings numpy, which the CLI's start does without)."""
    import importlib
    import importlib.util
    if name == 'Parameter':
        from zros.parameter import Parameter
        return Parameter
    if not name.startswith('_') and importlib.util.find_spec(f'zros.{name}') is not None:
        return importlib.import_module(f'zros.{name}')
    raise AttributeError(f"module 'zros' has no attribute '{name}'")
