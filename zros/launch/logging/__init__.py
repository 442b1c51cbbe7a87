"""launch.logging: the launch's loggers, its screen and log file handlers, and the loggers a
process's output goes to (`get_output_loggers(name, 'screen' | 'log' | 'both' | 'own_log' |
'full' | {source: destinations})`).

Code written against launch configures its output through `launch_config` (level, log
directory, screen and file formats, the log file handler factory). Every logger made after
this module is imported is a launch logger: it does not propagate to the root logger, so its
records reach exactly the handlers the configuration gave it, and `reset()` can clear them all.
"""
from __future__ import annotations

import datetime
import logging
import os
import socket
import sys
import warnings
from typing import Any, Callable

from zros.launch.logging import handlers
from zros.logging import get_logging_directory

__all__ = ['get_logger', 'get_output_loggers', 'handlers', 'launch_config', 'reset', 'log_launch_config',
           'LaunchConfig', 'LaunchLogger']

#: The format aliases (style '{'): `default` on screen has no time, the log file's has.
_SCREEN_FORMATS = {'default': '[{levelname}] [{name}]: {msg}',
                   'default_with_timestamp': '{created:.7f} [{levelname}] [{name}]: {msg}'}
_LOG_FORMATS = {'default': '{created:.7f} [{levelname}] [{name}]: {msg}'}

#: `output=` aliases: for each source (stdout, stderr, both), where its lines go.
_OUTPUT_ALIASES: dict[str, dict[str, set[str]]] = {
    'screen': {'both': {'screen'}},
    'log': {'both': {'log'}, 'stderr': {'screen'}},
    'both': {'both': {'log', 'screen'}},
    'own_log': {'both': {'own_log'}, 'stdout': {'own_log'}, 'stderr': {'own_log'}},
    'full': {'both': {'screen', 'log', 'own_log'}, 'stdout': {'own_log'}, 'stderr': {'own_log'}},
}
_SOURCES = ('stdout', 'stderr', 'both')
_DESTINATIONS = ('screen', 'log', 'own_log')


def _get_logging_directory() -> str:
    """ROS 2's log directory ($ROS_LOG_DIR, else $ROS_HOME/log, else ~/.ros/log), normalized."""
    return os.path.normpath(str(get_logging_directory()))


def _make_unique_log_dir(*, base_path: str) -> str:
    """Create and return `<base_path>/<date-time>-<host>-<pid>`, a directory no other launch has."""
    while True:
        stamp = datetime.datetime.now().strftime('%Y-%m-%d-%H-%M-%S-%f')
        log_dir = os.path.join(base_path, f'{stamp}-{socket.gethostname()}-{os.getpid()}')
        if not os.path.isdir(log_dir):
            os.makedirs(log_dir, exist_ok=True)
            return log_dir


def _renew_latest_log_dir(*, log_dir: str) -> bool:
    """Point `<base>/latest` at `log_dir`; False when `latest` exists and is no symlink."""
    latest = os.path.join(os.path.dirname(log_dir), 'latest')
    if os.path.lexists(latest):
        if not os.path.islink(latest):
            return False
        os.unlink(latest)
    os.symlink(log_dir, latest, target_is_directory=True)
    return True


class _CurrentStdout:
    """sys.stdout as it is at each write (a test's capture, a redirected stream), not as it was
    when the screen handler was made."""

    def write(self, text: str) -> int:
        return sys.stdout.write(text)

    def flush(self) -> None:
        sys.stdout.flush()


def _formatter(text: str, style: str | None, aliases: dict[str, str], what: str) -> logging.Formatter:
    """A '{'-style formatter for an alias, or for `text` in `style` (default '{'); an alias
    takes no style (ValueError)."""
    if text in aliases:
        if style is not None:
            raise ValueError(f"cannot set a custom format style for the '{text}' {what} format")
        return logging.Formatter(aliases[text], style='{')
    return logging.Formatter(text, style=style or '{')


def _overridden(variable: str) -> str | None:
    """The format an OVERRIDE_LAUNCH_*_FORMAT variable sets (escapes such as \\t decoded)."""
    value = os.environ.get(variable)
    return value.encode('latin1').decode('unicode_escape') if value else None


class LaunchConfig:
    """The launch's logging configuration: one per process, `launch_config`."""

    def __init__(self) -> None:
        self.reset()

    def reset(self) -> None:
        """Forget the log directory and handlers; INFO and the default formats again."""
        self._log_dir: str | None = None
        self._log_handler_factory: Callable[..., logging.Handler] | None = None
        self.file_handlers: dict[str, logging.Handler] = {}
        self.screen_handler: logging.Handler | None = None
        self.screen_formatter: logging.Formatter | None = None
        self.file_formatter: logging.Formatter | None = None
        logging.root.setLevel(logging.INFO)
        self.set_screen_format('default')
        self.set_log_format('default')

    @property
    def level(self) -> int:
        """Every launch logger's default level (the root logger's)."""
        return logging.root.getEffectiveLevel()

    @level.setter
    def level(self, new_level: int | str) -> None:
        logging.root.setLevel(new_level)

    @property
    def log_dir(self) -> str:
        """This launch's log directory, made (with a `latest` link beside it) on first use."""
        if self._log_dir is None:
            self._log_dir = _make_unique_log_dir(base_path=_get_logging_directory())
            try:
                if not _renew_latest_log_dir(log_dir=self._log_dir):
                    warnings.warn('cannot create a symlink to the latest log directory')
            except OSError as exc:
                warnings.warn(f'cannot create a symlink to the latest log directory: {exc}')
        return self._log_dir

    @log_dir.setter
    def log_dir(self, new_log_dir: str | None) -> None:
        """An existing directory, or None to make one on next use. Raises ValueError otherwise."""
        if new_log_dir is not None:
            if self.file_handlers:
                warnings.warn(f'log files are already open below {self._log_dir}; they stay there')
            if not os.path.isdir(new_log_dir):
                raise ValueError(f'{new_log_dir} is not a directory')
        self._log_dir = new_log_dir

    @property
    def log_handler_factory(self) -> Callable[..., logging.Handler]:
        """`factory(path, encoding=...)` -> the handler for a log file (default: a file handler
        that reopens the file when it is rotated away)."""
        if self._log_handler_factory is None:
            self._log_handler_factory = handlers.WatchedFileHandler if os.name != 'nt' else handlers.FileHandler
        return self._log_handler_factory

    @log_handler_factory.setter
    def log_handler_factory(self, factory: Callable[..., logging.Handler] | None) -> None:
        self._log_handler_factory = factory

    def set_screen_format(self, screen_format: str | None, *, screen_style: str | None = None) -> None:
        """The screen's format: 'default', 'default_with_timestamp', or a logging format in
        `screen_style`; $OVERRIDE_LAUNCH_SCREEN_FORMAT ('{' style) wins over both."""
        override = _overridden('OVERRIDE_LAUNCH_SCREEN_FORMAT')
        if override is not None:
            screen_format, screen_style = override, '{'
        self.screen_formatter = (None if screen_format is None else
                                 _formatter(screen_format, screen_style, _SCREEN_FORMATS, 'screen'))
        if self.screen_handler is not None and self.screen_formatter is not None:
            self.screen_handler.setFormatter(self.screen_formatter)

    def set_log_format(self, log_format: str | None, *, log_style: str | None = None) -> None:
        """The launch log file's format: 'default' or a logging format in `log_style`;
        $OVERRIDE_LAUNCH_LOG_FORMAT ('{' style) wins over both."""
        override = _overridden('OVERRIDE_LAUNCH_LOG_FORMAT')
        if override is not None:
            log_format, log_style = override, '{'
        self.file_formatter = None if log_format is None else _formatter(log_format, log_style, _LOG_FORMATS, 'log')
        for handler in self.file_handlers.values():
            handler.setFormatter(self.file_formatter)

    def get_screen_handler(self) -> logging.Handler:
        """The one screen handler (standard output)."""
        if self.screen_handler is None:
            self.screen_handler = handlers.StreamHandler(_CurrentStdout())
            self.screen_handler.setFormatter(self.screen_formatter)
        return self.screen_handler

    def get_log_file_path(self, file_name: str = 'launch.log') -> str:
        return os.path.join(self.log_dir, file_name)

    def get_log_file_handler(self, file_name: str = 'launch.log') -> logging.Handler:
        """The handler of log file `file_name` in the log directory (one per file name)."""
        if file_name not in self.file_handlers:
            handler = self.log_handler_factory(self.get_log_file_path(file_name), encoding='utf-8')
            handler.setFormatter(self.file_formatter)
            self.file_handlers[file_name] = handler
        return self.file_handlers[file_name]


launch_config = LaunchConfig()


def log_launch_config(*, logger: logging.Logger = logging.root) -> None:
    """Tell the user where the log files are and at which level the launch logs."""
    if launch_config.file_handlers:
        logger.info(f'All log files can be found below {launch_config.log_dir}')
    logger.info(f'Default logging verbosity is set to {logging.getLevelName(logging.root.getEffectiveLevel())}')


def _add_once(logger: logging.Logger, handler: logging.Handler) -> None:
    if handler not in logger.handlers:
        logger.addHandler(handler)


def get_logger(name: str | None = None) -> logging.Logger:
    """Logger `name`, writing to the screen and the launch log file."""
    logger = logging.getLogger(name)
    _add_once(logger, launch_config.get_screen_handler())
    _add_once(logger, launch_config.get_log_file_handler())
    return logger


def _normalize_output_configuration(config: Any) -> dict[str, set[str]]:
    """`output=` as {'stdout', 'stderr', 'both'} -> destinations; ValueError names what is wrong."""
    normalized: dict[str, set[str]] = {source: set() for source in _SOURCES}
    if isinstance(config, str):
        if config not in _OUTPUT_ALIASES:
            raise ValueError(f"{config} is not a valid output configuration: use {', '.join(_OUTPUT_ALIASES)}")
        normalized.update({source: set(where) for source, where in _OUTPUT_ALIASES[config].items()})
        return normalized
    if not isinstance(config, dict):
        raise ValueError(f'{config!r} is not a valid output configuration')
    for source, destinations in config.items():
        if source not in _SOURCES:
            raise ValueError(f"{source} is not a valid output source: use {', '.join(_SOURCES)}")
        destinations = {destinations} if isinstance(destinations, str) else set(destinations)
        unknown = destinations - set(_DESTINATIONS)
        if unknown:
            raise ValueError(f"{', '.join(sorted(unknown))} is not a valid output destination: "
                             f"use {', '.join(_DESTINATIONS)}")
        normalized[source] = destinations
    return normalized


def get_output_loggers(process_name: str, output_config: Any) -> tuple[logging.Logger, logging.Logger]:
    """The (stdout, stderr) loggers of process `process_name`, sending its lines where
    `output_config` says: 'screen' (bare lines), 'log' (the launch log, time-stamped) and
    'own_log' (`<name>-stdout.log` / `<name>-stderr.log`; for 'both', `<name>.log`)."""
    config = _normalize_output_configuration(output_config)
    for source in ('stdout', 'stderr'):
        logger = logging.getLogger(f'{process_name}-{source}')
        wanted = config['both'] | config[source]
        if 'screen' in wanted:
            screen = launch_config.get_screen_handler()
            screen.setFormatterFor(logger, logging.Formatter('{msg}', style='{'))
            _add_once(logger, screen)
        if 'log' in wanted:
            main_log = launch_config.get_log_file_handler()
            main_log.setFormatterFor(logger, logging.Formatter('{created:.7f} {msg}', style='{'))
            _add_once(logger, main_log)
        if 'own_log' in config[source]:
            own = launch_config.get_log_file_handler(f'{process_name}-{source}.log')
            own.setFormatter(logging.Formatter(fmt=None))
            _add_once(logger, own)
        if 'own_log' in config['both']:
            combined = launch_config.get_log_file_handler(f'{process_name}.log')
            combined.setFormatter(logging.Formatter('{msg}', style='{'))
            _add_once(logger, combined)
    return logging.getLogger(f'{process_name}-stdout'), logging.getLogger(f'{process_name}-stderr')


class LaunchLogger(logging.getLoggerClass()):  # type: ignore[misc]
    """A logger that keeps to its own handlers (no propagation), remembered so that `reset()`
    can clear it."""

    all_loggers: list[logging.Logger] = []

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.propagate = False
        LaunchLogger.all_loggers.append(self)


def reset() -> None:
    """Every launch logger back to no handlers and no level of its own; `launch_config` reset."""
    for logger in LaunchLogger.all_loggers:
        logger.setLevel(logging.NOTSET)
        del logger.handlers[:]
    launch_config.reset()
    logging.setLoggerClass(LaunchLogger)


reset()
