"""The logger services of a node started with `enable_logger_service=True`, as in rclpy:
`<node>/get_logger_levels` and `<node>/set_logger_levels` (rcl_interfaces), so a running node's
log levels can be read and changed from outside (`zros service call ...`)."""
from __future__ import annotations

from typing import TYPE_CHECKING, Any

from zros.logging import LoggingSeverity, get_logger_level, set_logger_level

if TYPE_CHECKING:
    from zros.node import Node

__all__ = ['LoggingService']


class LoggingService:
    """Made by Node; the two services live (and are destroyed) with the node."""

    def __init__(self, node: 'Node') -> None:
        from interfaces.rcl_interfaces.srv import GetLoggerLevels, SetLoggerLevels
        name = node.get_name()
        node.create_service(GetLoggerLevels, f'{name}/get_logger_levels', self._get_levels)
        node.create_service(SetLoggerLevels, f'{name}/set_logger_levels', self._set_levels)

    @staticmethod
    def _get_levels(request: Any, response: Any) -> Any:
        from interfaces.rcl_interfaces.msg import LoggerLevel
        response.levels = [LoggerLevel(name=name, level=int(get_logger_level(name))) for name in request.names]
        return response

    @staticmethod
    def _set_levels(request: Any, response: Any) -> Any:
        from interfaces.rcl_interfaces.msg import SetLoggerLevelsResult
        results = []
        for entry in request.levels:
            try:
                set_logger_level(entry.name, LoggingSeverity(entry.level))
                results.append(SetLoggerLevelsResult(successful=True))
            except ValueError:
                results.append(SetLoggerLevelsResult(successful=False, reason='Failed reason: Invalid logger level.'))
        response.results = results
        return response
