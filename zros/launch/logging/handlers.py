"""launch.logging.handlers: the standard library's logging handlers, each able to format the
records of one logger its own way (`handler.setFormatterFor(logger, formatter)`).

One screen handler and one launch log file handler are shared by every logger in a launch;
process output goes through them bare (`{msg}`) while launch's own messages carry level and
name, so the format has to be chosen per logger, not per handler.
"""
from __future__ import annotations

import logging
import logging.handlers
from typing import Any

__all__ = ['with_per_logger_formatting', 'Handler', 'StreamHandler', 'FileHandler', 'WatchedFileHandler',
           'RotatingFileHandler', 'TimedRotatingFileHandler', 'NullHandler']


class PerLoggerFormatting:
    """Mixin for a logging.Handler: formatters chosen by the record's logger name, falling back
    to the handler's own formatter."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._formatters: dict[str, logging.Formatter] = {}

    def setFormatterFor(self, logger: logging.Logger | str, formatter: logging.Formatter) -> None:  # noqa: N802
        """Format records of `logger` (a logger or its name) with `formatter`."""
        self._formatters[logger if isinstance(logger, str) else logger.name] = formatter

    def unsetFormatterFor(self, logger: logging.Logger | str) -> None:  # noqa: N802
        """Back to the handler's own formatter for `logger`."""
        self._formatters.pop(logger if isinstance(logger, str) else logger.name, None)

    def format(self, record: logging.LogRecord) -> str:  # noqa: A003 - logging.Handler's name
        formatter = self._formatters.get(record.name)
        return formatter.format(record) if formatter is not None else super().format(record)


def with_per_logger_formatting(cls: type[logging.Handler]) -> type[logging.Handler]:
    """`cls` with PerLoggerFormatting mixed in, under the same name."""
    return type(cls.__name__, (PerLoggerFormatting, cls), {'__doc__': cls.__doc__, '__module__': __name__})


Handler = with_per_logger_formatting(logging.Handler)
StreamHandler = with_per_logger_formatting(logging.StreamHandler)
FileHandler = with_per_logger_formatting(logging.FileHandler)
WatchedFileHandler = with_per_logger_formatting(logging.handlers.WatchedFileHandler)
RotatingFileHandler = with_per_logger_formatting(logging.handlers.RotatingFileHandler)
TimedRotatingFileHandler = with_per_logger_formatting(logging.handlers.TimedRotatingFileHandler)
NullHandler = with_per_logger_formatting(logging.NullHandler)
