"""Loggers with rclpy's interface and ROS 2's console format.

`[INFO] [1700000000.123456789] [talker]: Publishing: 'Hello World: 1'` on stderr, as
rcutils prints it (RCUTILS_CONSOLE_OUTPUT_FORMAT, RCUTILS_COLORIZED_OUTPUT and
RCUTILS_LOGGING_USE_STDOUT are honoured). Nodes also forward their records to /rosout
through `add_sink`.
"""
from __future__ import annotations

import enum
import inspect
import os
import sys
import threading
import time
from typing import Callable

__all__ = ['LoggingSeverity', 'RcutilsLogger', 'get_logger', 'set_logger_level',
           'get_logger_level', 'add_sink', 'remove_sink', 'severity_from_string']


class LoggingSeverity(enum.IntEnum):
    UNSET = 0
    DEBUG = 10
    INFO = 20
    WARN = 30
    ERROR = 40
    FATAL = 50


_NAMES = {LoggingSeverity.DEBUG: 'DEBUG', LoggingSeverity.INFO: 'INFO', LoggingSeverity.WARN: 'WARN',
          LoggingSeverity.ERROR: 'ERROR', LoggingSeverity.FATAL: 'FATAL'}
_COLORS = {LoggingSeverity.DEBUG: '\033[32m', LoggingSeverity.WARN: '\033[33m',
           LoggingSeverity.ERROR: '\033[31m', LoggingSeverity.FATAL: '\033[31m'}
_DEFAULT_FORMAT = '[{severity}] [{time}] [{name}]: {message}'

_levels: dict[str, LoggingSeverity] = {'': LoggingSeverity.INFO}
_sinks: list[Callable[[LoggingSeverity, str, str, int, str, str, int], None]] = []
_lock = threading.Lock()


def severity_from_string(text: str) -> LoggingSeverity:
    key = text.strip().upper()
    if key == 'WARNING':
        key = 'WARN'
    try:
        return LoggingSeverity[key]
    except KeyError:
        raise ValueError(f"unknown log level '{text}': use debug, info, warn, error or fatal") from None


def set_logger_level(name: str, level: LoggingSeverity | int | str) -> None:
    """Set a logger's level; '' is the default level for every logger."""
    if isinstance(level, str):
        level = severity_from_string(level)
    _levels[name] = LoggingSeverity(level)


def get_logger_level(name: str) -> LoggingSeverity:
    return _levels.get(name, LoggingSeverity.UNSET)


def _effective_level(name: str) -> LoggingSeverity:
    while True:
        level = _levels.get(name)
        if level:
            return level
        if not name:
            return LoggingSeverity.INFO
        name = name.rpartition('.')[0]


def add_sink(sink: Callable[[LoggingSeverity, str, str, int, str, str, int], None]) -> None:
    """Register `sink(severity, logger_name, message, time_ns, file, function, line)`."""
    with _lock:
        _sinks.append(sink)


def remove_sink(sink: Callable) -> None:
    with _lock:
        if sink in _sinks:
            _sinks.remove(sink)


def _emit(severity: LoggingSeverity, name: str, message: str, caller: inspect.Traceback | None) -> None:
    now = time.time_ns()
    fmt = os.environ.get('RCUTILS_CONSOLE_OUTPUT_FORMAT', _DEFAULT_FORMAT)
    stamp = f'{now // 1_000_000_000}.{now % 1_000_000_000:09d}'
    file, function, line = (caller.filename, caller.function, caller.lineno) if caller else ('', '', 0)
    try:
        text = fmt.format(severity=_NAMES[severity], time=stamp, name=name, message=message,
                          file_name=file, function_name=function, line_number=line,
                          date_time_with_ms=time.strftime('%Y-%m-%d %H:%M:%S', time.localtime(now / 1e9)))
    except (KeyError, IndexError, ValueError):
        text = _DEFAULT_FORMAT.format(severity=_NAMES[severity], time=stamp, name=name, message=message)
    stream = sys.stdout if os.environ.get('RCUTILS_LOGGING_USE_STDOUT') == '1' else sys.stderr
    color = os.environ.get('RCUTILS_COLORIZED_OUTPUT')
    use_color = color == '1' or (color is None and stream.isatty())
    if use_color and severity in _COLORS:
        text = f'{_COLORS[severity]}{text}\033[0m'
    try:
        stream.write(text + '\n')
        stream.flush()
    except (OSError, ValueError):
        pass  # a closed terminal must not kill the node
    for sink in list(_sinks):
        sink(severity, name, message, now, file, function, line)


class RcutilsLogger:
    """rclpy's logger: severity methods with `once`, `skip_first` and `throttle_duration_sec`."""

    def __init__(self, name: str = '') -> None:
        self.name = name
        self._call_state: dict[tuple, list] = {}

    def get_child(self, name: str) -> 'RcutilsLogger':
        if not name:
            raise ValueError('child logger name must not be empty')
        return RcutilsLogger(f'{self.name}.{name}' if self.name else name)

    def set_level(self, level: LoggingSeverity | int | str) -> None:
        set_logger_level(self.name, level)

    def get_effective_level(self) -> LoggingSeverity:
        return _effective_level(self.name)

    def is_enabled_for(self, severity: LoggingSeverity | int) -> bool:
        return severity >= _effective_level(self.name)

    def log(self, message: object, severity: LoggingSeverity | int, *, once: bool = False,
            skip_first: bool = False, throttle_duration_sec: float | None = None,
            throttle_time_source_type: object = None, _stack: int = 1) -> bool:
        """Log `message`; returns whether it was printed (like rclpy)."""
        severity = LoggingSeverity(severity)
        if severity < _effective_level(self.name):
            return False
        caller = None
        if once or skip_first or throttle_duration_sec or _sinks:
            frame = sys._getframe(_stack)
            caller = inspect.Traceback(frame.f_code.co_filename, frame.f_lineno,
                                       frame.f_code.co_name, None, None)
        if once or skip_first or throttle_duration_sec:
            key = (caller.filename, caller.lineno, severity)
            state = self._call_state.setdefault(key, [0, None])  # [calls, last_emit_monotonic]
            state[0] += 1
            if once and state[0] > 1:
                return False
            if skip_first and state[0] == 1:
                return False
            if throttle_duration_sec:
                now = time.monotonic()
                if state[1] is not None and now - state[1] < throttle_duration_sec:
                    return False
                state[1] = now
        _emit(severity, self.name, str(message), caller)
        return True

    def debug(self, message: object, **kwargs) -> bool:
        return self.log(message, LoggingSeverity.DEBUG, _stack=2, **kwargs)

    def info(self, message: object, **kwargs) -> bool:
        return self.log(message, LoggingSeverity.INFO, _stack=2, **kwargs)

    def warn(self, message: object, **kwargs) -> bool:
        return self.log(message, LoggingSeverity.WARN, _stack=2, **kwargs)

    warning = warn

    def error(self, message: object, **kwargs) -> bool:
        return self.log(message, LoggingSeverity.ERROR, _stack=2, **kwargs)

    def fatal(self, message: object, **kwargs) -> bool:
        return self.log(message, LoggingSeverity.FATAL, _stack=2, **kwargs)


def get_logger(name: str) -> RcutilsLogger:
    return RcutilsLogger(name)
