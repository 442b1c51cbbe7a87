"""`launch_testing.tools`: matching expected output (text, regex patterns, or a sequence of
them, in order) and filtering output lines before matching."""
from __future__ import annotations

import os
import re
from collections.abc import Iterable
from typing import Any, Callable

__all__ = ['basic_output_filter', 'expected_output_from_file', 'expect_output', 'find_text',
           'strip_ansi']

_ANSI = re.compile(r'\x1b\[[0-9;?]*[ -/]*[@-~]')


def strip_ansi(text: str) -> str:
    """`text` without terminal colour and cursor escape sequences."""
    return _ANSI.sub('', text)


def find_text(expected: Any, text: str, start: int = 0) -> tuple[int, int] | None:
    """Where `expected` is in `text` from `start`: (begin, end), or None.

    `expected` is a string (found anywhere), a compiled regex (searched), or an iterable of
    those, which must all be found one after the other.
    """
    text = text.replace('\r\n', '\n')
    if isinstance(expected, str):
        found = text.find(expected, start)
        return None if found < 0 else (found, found + len(expected))
    if hasattr(expected, 'search'):
        match = expected.search(text, start)
        return None if match is None else (match.start(), match.end())
    if isinstance(expected, Iterable):
        begin, end = None, start
        for item in expected:
            span = find_text(item, text, end)
            if span is None:
                return None
            begin = span[0] if begin is None else begin
            end = span[1]
        return (start if begin is None else begin, end)
    raise ValueError(f'expected output is a str, a regex or a list of them, not {type(expected).__name__}')


def basic_output_filter(filtered_prefixes: list[str] | None = None,
                        filtered_patterns: list[str] | None = None) -> Callable[[str], str]:
    """A filter that drops the lines starting with one of `filtered_prefixes` (default: 'pid',
    'rc') or matching one of `filtered_patterns`."""
    prefixes = tuple(['pid', 'rc'] if filtered_prefixes is None else filtered_prefixes)
    patterns = [re.compile(p) for p in filtered_patterns or []]

    def keep(line: str) -> bool:
        return not line.startswith(prefixes) and not any(p.match(line) for p in patterns)
    return lambda output: ''.join(line for line in output.splitlines(keepends=True) if keep(line))


def expected_output_from_file(path: str, encoding: str | None = None) -> list:
    """The lines of `path.txt`, or the patterns of `path.regex` (one per line)."""
    for suffix, make in (('.txt', str), ('.regex', re.compile)):
        if os.path.isfile(path + suffix):
            with open(path + suffix, encoding=encoding) as handle:
                return [make(line) for line in handle.read().splitlines()]
    raise RuntimeError(f'could not find output check file: {path}(.txt or .regex)')


def expect_output(text: str | None = None, *, lines: list[str] | None = None, expected_text: Any = None,
                  expected_lines: Any = None, strip_ansi_escape_sequences: bool = True, strict: bool = False) -> bool:
    """Whether the output (`text` or `lines`) holds the expectation (`expected_text`, or
    `expected_lines` each within one line); `strict` asks for exactly that and nothing else."""
    if (text is None) == (lines is None) or (expected_text is None) == (expected_lines is None):
        raise ValueError('give text or lines, and expected_text or expected_lines (one of each)')
    if text is None:
        text = '\n'.join(lines)
    if strip_ansi_escape_sequences:
        text = strip_ansi(text)
    if expected_text is not None:
        span = find_text(expected_text, text)
        return span is not None and (not strict or span == (0, len(text)))
    actual = text.splitlines()
    expected = [expected_lines] if isinstance(expected_lines, str) or hasattr(expected_lines, 'search') \
        else list(expected_lines)
    if strict:
        return len(actual) == len(expected) and all(find_text(e, a) is not None for e, a in zip(expected, actual))
    index = 0
    for item in expected:
        index = next((i + 1 for i in range(index, len(actual)) if find_text(item, actual[i]) is not None), -1)
        if index < 0:
            return False
    return True
