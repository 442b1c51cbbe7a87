"""Reading a launch file, Python, YAML or XML, into actions.

The front ends meet here: a `.py` file is imported and its `generate_launch_description()`
called, a `.yaml` / `.yml` or `.xml` file is parsed tag by tag; all give a list of the same
action objects. Whatever goes wrong while reading is one `LaunchFileError` line that names the file and
line: a Python exception in the launch file, a module that is not there, a
class zros does not have (with the list of those it has), a binary or non-UTF-8 file.
"""
from __future__ import annotations

import hashlib
import importlib.util
import os
import re
import traceback
from types import ModuleType
from typing import Any, Callable

from zros.launch.errors import LaunchError, LaunchFileError, LaunchFileNotFoundError

__all__ = ['load_launch_file', 'load_launch_description', 'read_text', 'launch_file_kind', 'python_error',
           'InvalidPythonLaunchFileError', 'load_python_launch_file_as_module',
           'get_launch_description_from_python_launch_file']

_CANNOT_IMPORT = re.compile(r"cannot import name '(\w+)' from '([\w.]+)'")


def launch_file_kind(path: str) -> str:
    """'python', 'yaml', or 'xml' from the file name."""
    lower = path.lower()
    if lower.endswith('.py'):
        return 'python'
    if lower.endswith(('.xml', '.launch')):   # launch_xml's extensions
        return 'xml'
    return 'yaml'


def read_text(path: str, what: str = 'launch file') -> str:
    """A text file's content; LaunchFileError (one line) when it is missing, unreadable or binary."""
    try:
        data = open(path, 'rb').read()
    except FileNotFoundError:
        raise LaunchFileNotFoundError(None, f'{path}: no such {what}') from None
    except IsADirectoryError:
        raise LaunchFileError(None, f'{path}: is a directory, not a {what}') from None
    except OSError as exc:
        raise LaunchFileError(None, f'{path}: cannot read {what}: {exc.strerror}') from None
    try:
        text = data.decode('utf-8')
    except UnicodeDecodeError:
        text = None
    if text is None or '\x00' in text:
        raise LaunchFileError(None, f'{path}: not a {what}: binary data, not UTF-8 text')
    return text


def load_launch_file(path: str, kind: str | None = None) -> list:
    """The actions of a launch file (nothing is resolved or started)."""
    return load_launch_description(path, kind).entities


def load_launch_description(path: str, kind: str | None = None) -> Any:
    """A launch file's LaunchDescription: a Python file's `generate_launch_description()`, or
    the parsed YAML / XML (`kind` as `launch_file_kind` names it; None: by the file name)."""
    if kind is None and not path.lower().endswith(_KNOWN_EXTENSIONS):
        return _load_any_markup(path)
    kind = kind or launch_file_kind(path)
    if kind == 'python':
        return get_launch_description_from_python_launch_file(path)
    from zros.launch.frontend.formats import XmlParser, YamlParser
    root, parser = (XmlParser if kind == 'xml' else YamlParser).load(path)
    return parser.parse_description(root)


_KNOWN_EXTENSIONS = ('.py', '.xml', '.launch', '.yaml', '.yml')


def _load_any_markup(path: str) -> Any:
    """A file whose name says no format: YAML, else XML, as launch tries its front ends; an
    InvalidLaunchFileError naming both failures when neither reads it."""
    from zros.launch.invalid_launch_file_error import InvalidLaunchFileError
    errors: list[LaunchFileError] = []
    for kind in ('yaml', 'xml'):
        try:
            return load_launch_description(path, kind)
        except LaunchFileNotFoundError:
            raise
        except LaunchFileError as exc:
            errors.append(exc)
    raise InvalidLaunchFileError(f'{os.path.splitext(path)[1] or path}: yaml, xml', likely_errors=errors)


# -- Python launch files ------------------------------------------------------------------------
class InvalidPythonLaunchFileError(LaunchFileError):
    """A Python file that is no launch file: it has no `generate_launch_description()`, or that
    returns no LaunchDescription (launch's error of that name)."""


def load_python_launch_file_as_module(path: str) -> ModuleType:
    """Import a Python launch file as a module of its own (under the import hook, so `launch` is
    zros.launch there); any exception it raises is one `file:line: what` LaunchFileError.

    Raises:
        LaunchFileNotFoundError: there is no such file (also a FileNotFoundError).
    """
    from zros.import_hook import install
    text = read_text(path)
    install()   # a launch file as ROS 2 writes it: `from launch import ...` is zros.launch itself
    name = 'zros_launch_file_' + hashlib.sha1(os.path.abspath(path).encode()).hexdigest()[:12]
    module = importlib.util.module_from_spec(importlib.util.spec_from_file_location(name, path))
    _run_user_code(path, lambda: exec(compile(text, path, 'exec'), module.__dict__))  # noqa: S102 - the user's file
    return module


def get_launch_description_from_python_launch_file(path: str) -> Any:
    """The LaunchDescription a Python launch file's `generate_launch_description()` returns.

    Raises:
        InvalidPythonLaunchFileError: the file defines no such function or it returns no
            LaunchDescription.
        LaunchFileNotFoundError: there is no such file.
    """
    from zros.launch.launch_description import LaunchDescription
    generate = getattr(load_python_launch_file_as_module(path), 'generate_launch_description', None)
    if not callable(generate):
        raise InvalidPythonLaunchFileError(None, f'{path}: no generate_launch_description() function '
                                                 '(a Python launch file defines one that returns a LaunchDescription)')
    description = _run_user_code(path, generate)
    if not isinstance(description, LaunchDescription):
        raise InvalidPythonLaunchFileError(None, f'{path}: generate_launch_description() returned '
                                                 f'{type(description).__name__}, not a LaunchDescription')
    return description


def _run_user_code(path: str, run: Callable[[], Any]) -> Any:
    """`run()`, code of the user's file `path`; whatever it raises becomes one LaunchFileError line."""
    try:
        return run()
    except LaunchError:
        raise
    except SyntaxError as exc:
        raise LaunchFileError(None, f'{path}:{exc.lineno or 1}: invalid Python: {exc.msg}') from None
    except Exception as exc:  # noqa: BLE001 - anything the user's file raises becomes one line
        raise python_error(path, exc) from None


def _frame_in(path: str, exc: BaseException) -> tuple[int, str]:
    """The line number and text of `path` nearest to where `exc` was raised ((1, '') if the file
    is not on the stack)."""
    line, text = 1, ''
    real = os.path.realpath(path)
    for frame in traceback.extract_tb(exc.__traceback__):
        if os.path.realpath(frame.filename) == real:
            line, text = frame.lineno or line, frame.line or ''
    return line, text


def python_error(path: str, exc: Exception) -> LaunchFileError:
    """One `file:line: what` error for an exception a user's Python file (launch file or launch
    test) raised: the line is the deepest frame in that file."""
    line, text = _frame_in(path, exc)
    where = f'{path}:{line}'
    if isinstance(exc, KeyError) and 'environ' in text and exc.args and exc.args[0] not in os.environ:
        # `os.environ['TURTLEBOT3_MODEL']`, as course launch files read the robot model
        return LaunchFileError(None, f"{where}: KeyError: environment variable {exc.args[0]!r} is not set "
                                     f"(export {exc.args[0]}=...)")
    if isinstance(exc, ModuleNotFoundError) and exc.name:
        return LaunchFileError(None, f'{where}: {_missing_module(exc.name, text)}')
    if isinstance(exc, ImportError):
        match = _CANNOT_IMPORT.search(str(exc))
        if match and match.group(2).startswith('zros.'):
            return LaunchFileError(None, f'{where}: {unsupported(match.group(2), match.group(1))}')
    if isinstance(exc, AttributeError) and str(exc).startswith('zros.') and ' has no ' in str(exc):
        return LaunchFileError(None, f'{where}: {exc}')
    message = str(exc).strip().splitlines()[0] if str(exc).strip() else ''
    return LaunchFileError(None, f'{where}: {type(exc).__name__}' + (f': {message}' if message else ''))


def _missing_module(name: str, line: str = '') -> str:
    """Why a module a launch file imports is missing, by the name the import hook tried: a ROS
    library zros does not provide, an interface package not on the search path, or a module that
    is not installed."""
    if name.startswith('zros.'):
        return f"no module named '{name[5:]}' (a ROS library zros does not provide: no {name})"
    if name.startswith('interfaces.') or any(f'{name}.{kind}' in line for kind in ('msg', 'srv', 'action')):
        package = name.removeprefix('interfaces.').split('.')[0]
        return (f"no module named '{name.removeprefix('interfaces.')}' (no interface package "
                f"'{package}' here: see ZROS_INTERFACE_PATH in docs/packages.md)")
    return f"no module named '{name}' (not installed in this Python environment)"


def unsupported(module_name: str, name: str) -> str:
    """'zros.launch.actions has no ExecuteLocal; supported: ...' for a public launch module."""
    import sys
    module = sys.modules.get(module_name)
    names = sorted(n for n in getattr(module, '__all__', ()) if not n.startswith('_'))
    return f"{module_name} has no {name}; supported: {', '.join(names) or 'nothing'}"


def module_getattr(module_name: str):
    """A module `__getattr__` whose error says what the module has (`launch.actions.X` style
    access of a class zros does not provide)."""
    def __getattr__(name: str) -> Any:
        if name.startswith('__'):
            raise AttributeError(name)
        raise AttributeError(unsupported(module_name, name))
    return __getattr__
