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
from pathlib import Path
from collections.abc import Mapping
from typing import Any, Callable

__all__ = ['LoggingSeverity', 'RcutilsLogger', 'get_logger', 'set_logger_level',
           'get_logger_level', 'get_logger_effective_level', 'add_sink', 'remove_sink',
           'severity_from_string', 'get_logging_severity_from_string', 'clear_config',
           'get_logging_directory']


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

# Logger levels by name; '' is the root logger, whose level is every other logger's default.
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


def get_logging_severity_from_string(log_severity: str) -> LoggingSeverity:
    """rclpy's name for `severity_from_string`, raising RuntimeError (rcutils' error) for an
    unknown name."""
    try:
        return severity_from_string(log_severity)
    except ValueError as exc:
        raise RuntimeError(str(exc)) from None


def clear_config() -> None:
    """Forget every logger's level: all loggers follow the root logger again, at INFO."""
    with _lock:
        _levels.clear()
        _levels[''] = LoggingSeverity.INFO


def get_logging_directory(environ: Mapping[str, str] | None = None) -> Path:
    """Where ROS 2 keeps log files: $ROS_LOG_DIR, else $ROS_HOME/log, else ~/.ros/log, read
    from `environ` (a launch's environment, say) or else this process's."""
    environ = os.environ if environ is None else environ
    if environ.get('ROS_LOG_DIR'):
        return Path(os.path.expanduser(environ['ROS_LOG_DIR']))
    if environ.get('ROS_HOME'):
        return Path(os.path.expanduser(environ['ROS_HOME'])) / 'log'
    return Path(os.path.expanduser('~')) / '.ros' / 'log'


def set_logger_level(name: str, level: LoggingSeverity | int | str) -> None:
    """Set a logger's level; '' is the default level for every logger."""
    if isinstance(level, str):
        level = severity_from_string(level)
    _levels[name] = LoggingSeverity(level)


def get_logger_level(name: str) -> LoggingSeverity:
    return _levels.get(name, LoggingSeverity.UNSET)


def get_logger_effective_level(name: str) -> LoggingSeverity:
    """The level a logger logs at: its own, else its nearest ancestor's, else the root's."""
    return _effective_level(name)


def _effective_level(name: str) -> LoggingSeverity:
    while name:
        level = _levels.get(name)
        if level:
            return level
        name = name.rpartition('.')[0]
    return _levels.get('', LoggingSeverity.INFO)   # the root's own level, even UNSET


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


_LOG_OPTIONS = ('name', 'throttle_duration_sec', 'throttle_time_source_type', 'skip_first', 'once')


class _CallSite:
    """One call site of one logger: what it logs under, and what its filters remember."""

    def __init__(self, name: str, severity: LoggingSeverity, options: dict[str, Any]) -> None:
        self.name, self.severity, self.options = name, severity, options
        self.filtered = bool(options.get('once') or options.get('skip_first') or options.get('throttle_duration_sec'))
        self.last_emit: float | None = None
        self.skipped = False
        self.logged_once = False

    def passes(self) -> bool:
        """Run the throttle, skip_first and once filters, in that order (rclpy's)."""
        options = self.options
        duration = options.get('throttle_duration_sec')
        if duration:
            clock = options.get('throttle_time_source_type')
            now, last = _throttle_now(clock), self.last_emit
            if last is None and clock is not None:
                last = 0.0   # as rcutils: on a clock, the first message waits until it reads the duration
            if last is not None and now - last < duration:
                return False
            self.last_emit = now
        if options.get('skip_first') and not self.skipped:
            self.skipped = True
            return False
        if options.get('once'):
            if self.logged_once:
                return False
            self.logged_once = True
        return True


class RcutilsLogger:
    """rclpy's logger: severity methods with `once`, `skip_first` and `throttle_duration_sec`."""

    def __init__(self, name: str = '') -> None:
        self.name = name
        self._call_state: dict[tuple, _CallSite] = {}

    def get_child(self, name: str) -> 'RcutilsLogger':
        if not name:
            raise ValueError('Child logger name must not be empty')
        return RcutilsLogger(f'{self.name}.{name}' if self.name else name)

    def set_level(self, level: LoggingSeverity | int | str) -> None:
        set_logger_level(self.name, level)

    def get_effective_level(self) -> LoggingSeverity:
        return _effective_level(self.name)

    def is_enabled_for(self, severity: LoggingSeverity | int) -> bool:
        return severity >= _effective_level(self.name)

    def log(self, message: object, severity: LoggingSeverity | int, _stack: int = 1, **options: Any) -> bool:
        """Log `message` at `severity`, as rclpy does.

        Options (per call site; a call site that gives one must keep its name, severity and
        options from call to call, as rclpy insists; a plain call site is free):
        `throttle_duration_sec` (at most one message per this many seconds, timed on
        `throttle_time_source_type`, a Clock, or the monotonic clock), then `skip_first`, then
        `once` (each sees only the calls the one before let through); `name` logs under
        another logger name.

        :return: Whether the message was printed.
        :raises TypeError: For an unknown option, or a time source without a duration.
        :raises ValueError: If a call site's options or name change between calls.
        """
        unknown = [key for key in options if key not in _LOG_OPTIONS]
        if unknown:
            raise TypeError(f"parameter '{unknown[0]}' is not one of the recognized logging options "
                            f'({", ".join(_LOG_OPTIONS)})')
        if options.get('throttle_time_source_type') is not None and 'throttle_duration_sec' not in options:
            raise TypeError("required parameter 'throttle_duration_sec' not specified "
                            '(throttle_time_source_type needs it)')
        name = options.pop('name', self.name)
        severity = LoggingSeverity(severity)
        filtered = bool(options.get('once') or options.get('skip_first') or options.get('throttle_duration_sec'))
        caller = None
        if _sinks or filtered:
            frame = sys._getframe(_stack)
            caller = inspect.Traceback(frame.f_code.co_filename, frame.f_lineno, frame.f_code.co_name, None, None)
        if filtered:
            # A filtered call site remembers what it let through, so it must keep its name,
            # severity and options; a plain call keeps no state (and `(log.error if bad else
            # log.warn)(text)`, which rclpy refuses on its second call, works).
            site = self._call_site(caller.filename, caller.lineno, name, severity, options)
            if not site.passes():
                return False
        if severity < _effective_level(self.name):
            return False
        _emit(severity, name, str(message), caller)
        return True

    def _call_site(self, file: str, line: int, name: str, severity: LoggingSeverity,
                   options: dict[str, Any]) -> '_CallSite':
        """The state of the call site at `file`:`line`, which must keep its name, severity and
        options from call to call (as rclpy insists)."""
        site = self._call_state.get((file, line))
        if site is None:
            site = self._call_state[(file, line)] = _CallSite(name, severity, dict(options))
        elif site.name != name:
            raise ValueError('Logger name cannot be changed between calls from one call site')
        elif site.severity != severity:
            raise ValueError('Logger severity cannot be changed between calls from one call site')
        elif site.options != options:
            raise ValueError('Logging parameters cannot be changed between calls from one call site')
        return site

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


def _throttle_now(clock: Any) -> float:
    """Now [s] on the clock a throttle runs on: the monotonic clock unless one is given."""
    return time.monotonic() if clock is None else clock.now().nanoseconds / 1e9


def get_logger(name: str) -> RcutilsLogger:
    """A logger by name (`a.b` is a child of `a`).

    :raises ValueError: If `name` is empty (the root logger is not handed out, as in rclpy).
    """
    if not name:
        raise ValueError('Logger name must not be empty')
    return RcutilsLogger(name)


#: The root logger, whose level is the default of every other (rclpy's rclpy.logging._root_logger).
_root_logger = RcutilsLogger()
