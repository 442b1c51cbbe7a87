"""Templates: text with substitutions in it, the one form every launch value takes.

A YAML launch file writes substitutions as `$(name arg1 'arg 2' ...)`; a Python launch file
builds them as objects (`LaunchConfiguration('x')`, zros.launch.substitutions). Both end up as
the same `Template`: a tuple of literal strings and `Call`s of a registered substitution, so the
two front ends resolve, print and fail identically.

The text grammar is ROS 2's (launch/frontend/grammar.lark): outside a substitution everything is
literal, and a backslash escapes the next character (`\\$` is a dollar, `\\'` a quote); inside,
arguments are separated by spaces and may be quoted with `'` or `"` (quotes may hold spaces and
further substitutions). Parsing happens when the file is parsed, so an unknown substitution or a
wrong argument count is reported with the file, line, tag and key before anything runs;
evaluation happens while the launch is resolved.

`Text` and `Typed` are the deferred values that actions keep: a template plus where it was
written, so an evaluation error (`$(var missing)`) still names file:line, tag and key.
"""
from __future__ import annotations

import ast
import builtins
import importlib
import math
import os
import re
import secrets
import shlex
import shutil
import socket
import subprocess
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Protocol

from zros.launch.errors import ExpressionNameError, LaunchFileError, Origin, SubstitutionError

__all__ = [
    'Call', 'Template', 'parse', 'perform', 'is_static', 'describe', 'Text', 'Typed',
    'Substitution', 'TemplateSubstitution', 'to_template', 'SubstitutionContext', 'SUBSTITUTIONS', 'to_bool',
    'evaluate_expression', 'COMMAND_TIMEOUT_S',
]

#: `$(command ...)` is killed after this many seconds (a launch must never hang on it). Generous:
#: `xacro` is a Python start-up, which on a loaded machine has taken over 10 s of wall time.
COMMAND_TIMEOUT_S = 60.0


@dataclass(frozen=True)
class Call:
    """One `$(name args...)`; each argument is itself a template."""

    name: str
    args: tuple['Template', ...]


Template = tuple  # tuple[str | Call, ...]


class SubstitutionContext(Protocol):
    """What substitutions read; zros.launch.context.LaunchContext provides it."""

    configurations: dict[str, str]
    environment: dict[str, str]

    @property
    def current_file(self) -> str: ...

    @property
    def log_dir(self) -> str: ...

    def anon_name(self, name: str) -> str: ...


# -- parsing ----------------------------------------------------------------------------------
_IDENT = re.compile(r'[A-Za-z][A-Za-z0-9_-]*')


class _Parser:
    def __init__(self, text: str) -> None:
        self.s, self.i, self.n = text, 0, len(text)
        self.quote = ''   # the quote around the text being read: the other quote is text there

    def fail(self, reason: str, at: int | None = None) -> SubstitutionError:
        col = (self.i if at is None else at) + 1
        return SubstitutionError(f'{reason} (column {col} of {self.s!r})')

    def starts_call(self) -> bool:
        return self.s.startswith('$(', self.i)

    def take(self, parts: list, buf: list[str]) -> None:
        """One step through text: an escaped character, a substitution, or a character."""
        if self.s[self.i] == '\\' and self.i + 1 < self.n:
            buf.append(self.s[self.i + 1])
            self.i += 2
        elif self.starts_call():
            _flush(parts, buf)
            parts.append(self.call())
        else:
            buf.append(self.s[self.i])
            self.i += 1

    def template(self) -> Template:
        parts: list = []
        buf: list[str] = []
        while self.i < self.n:
            self.take(parts, buf)
        _flush(parts, buf)
        return tuple(parts)

    def call(self) -> Call | Substitution:
        start = self.i
        self.i += 2
        match = _IDENT.match(self.s, self.i)
        if not match:
            raise self.fail("expected a substitution name after '$('")
        name = match.group(0)
        self.i = match.end()
        args: list[Template] = []
        while True:
            if self.i >= self.n:
                raise self.fail(f"unterminated substitution '$({name}': missing ')'", start)
            char = self.s[self.i]
            if char == ')':
                self.i += 1
                break
            if char in ' \t':
                self.i += 1
                continue
            if not args and self.i == match.end():
                raise self.fail(f"expected a space or ')' after '$({name}'")
            args.append(self.argument())
        spec = SUBSTITUTIONS.get(name)
        if (spec is None or not spec.frontend) and name in _exposed():
            return self.exposed(name, args, start)
        if spec is None or not spec.frontend:
            known = ', '.join(sorted({*(n for n, s in SUBSTITUTIONS.items() if s.frontend), *_exposed()}))
            raise self.fail(f"unknown substitution '{name}' (known: {known})", start)
        if not spec.min_args <= len(args) <= (spec.max_args if spec.max_args >= 0 else len(args)):
            raise self.fail(f"'$({name})' takes {spec.arity_text()}, got {len(args)}", start)
        return Call(name, tuple(args))

    def exposed(self, name: str, args: list[Template], start: int) -> Substitution:
        """A substitution an extension exposed (`expose_substitution`), built by its parse
        method from launch's form of the arguments: one list of substitutions per argument."""
        from zros.launch.frontend.expose import instantiate_substitution
        from zros.launch.substitutions import substitutions_of
        try:
            return instantiate_substitution(name, [substitutions_of(arg) for arg in args])
        except Exception as exc:  # noqa: BLE001 - whatever an extension raises is the file's error
            raise self.fail(f"'$({name})': {str(exc) or type(exc).__name__}", start) from None

    def argument(self) -> Template:
        parts: list = []
        buf: list[str] = []
        while self.i < self.n:
            char = self.s[self.i]
            if char in ' \t)':
                break
            if char in '\'"' and char != _OTHER_QUOTE.get(self.quote):
                self.quoted(char, parts, buf)
            else:
                self.take(parts, buf)
        _flush(parts, buf)
        return tuple(parts)

    def quoted(self, quote: str, parts: list, buf: list[str]) -> None:
        start, outer = self.i, self.quote
        self.i += 1
        self.quote = quote
        while self.i < self.n:
            char = self.s[self.i]
            if char == quote:
                self.i += 1
                self.quote = outer
                return
            self.take(parts, buf)
        raise self.fail(f'unterminated {quote} quote', start)


#: launch's grammar: inside text quoted with one quote, the other one is an ordinary character,
#: also in the arguments of a substitution there (`$(env "a_$(var 'b')")` passes `'b'` to var).
_OTHER_QUOTE = {'"': "'", "'": '"'}


def _exposed() -> dict[str, Any]:
    """The substitutions extensions exposed (launch.frontend imports this module, hence late)."""
    from zros.launch.frontend.expose import substitution_parse_methods
    return substitution_parse_methods


def _flush(parts: list, buf: list[str]) -> None:
    if buf:
        parts.append(''.join(buf))
        buf.clear()


def parse(text: str) -> Template:
    """Parse a string into literal text and substitutions; SubstitutionError on bad syntax."""
    if '$' not in text and '\\' not in text:
        return (text,) if text else ()
    return _Parser(text).template()


def is_static(template: Template) -> bool:
    return all(isinstance(part, str) for part in template)


def describe(template: Template, quote: str = '') -> str:
    """The template written back as text (for --show-args defaults and --print); `quote` is
    the quote the text will stand in, which its substitutions' arguments must then use."""
    out = []
    for part in template:
        if isinstance(part, str):
            out.append(_describe_literal(part))
        elif isinstance(part, Substitution):
            out.append(part.describe())
        else:
            args = ''.join(' ' + _describe_arg(arg, quote) for arg in part.args)
            out.append(f'$({part.name}{args})')
    return ''.join(out)


def _describe_literal(text: str) -> str:
    return text.replace('\\', '\\\\').replace('$(', '\\$(')


def _describe_arg(arg: Template, outer: str = '') -> str:
    """One argument of a call, quoted when it must be: with the enclosing quote inside a quoted
    text (the other one is plain text there), else with `'` unless its text holds one. Only its
    literal parts are escaped for the quote; a call inside is written by the same rules."""
    text = describe(arg, outer)
    if text and not any(c in text for c in ' \t()\'"'):
        return text
    literals = ''.join(part for part in arg if isinstance(part, str))
    quote = outer or ("'" if "'" not in literals else '"')
    return quote + ''.join(_describe_literal(part).replace(quote, '\\' + quote) if isinstance(part, str)
                           else describe((part,), quote) for part in arg) + quote


def perform(template: Template, context: SubstitutionContext) -> str:
    """Evaluate a template; SubstitutionError (without location) when a substitution fails."""
    out = []
    for part in template:
        if isinstance(part, str):
            out.append(part)
        elif isinstance(part, Substitution):
            out.append(part.perform(context))
        else:
            spec = SUBSTITUTIONS[part.name]
            if spec.lazy:
                out.append(spec.function(context, [_Lazy(arg, context) for arg in part.args]))
            else:
                out.append(spec.function(context, [perform(arg, context) for arg in part.args]))
    return ''.join(out)


class _Lazy:
    """An argument of a lazy substitution (`var`, `env`, `if`, ...), evaluated only when the
    function asks: `$(var x $(var y))` does not fail on an unset `y` when `x` is set."""

    __slots__ = ('_template', '_context')

    def __init__(self, template: Template, context: SubstitutionContext) -> None:
        self._template, self._context = template, context

    def value(self) -> str:
        return perform(self._template, self._context)


# -- the Python face of a template ------------------------------------------------------------
class Substitution:
    """A value computed while the launch resolves (launch.Substitution).

    zros's own substitutions (zros.launch.substitutions) say what they are as a template of
    registered calls, so they print, resolve and fail exactly like their `$(...)` spelling. A
    user's subclass may instead override `perform(context)` (and `describe()`), as in ROS 2.
    """

    def template(self) -> Template:
        return (self,)

    def perform(self, context: Any) -> str:
        template = self.template()
        if template == (self,):
            raise NotImplementedError(f'{type(self).__name__} must define perform(context)')
        return perform(template, context)

    def describe(self) -> str:
        template = self.template()
        return type(self).__name__ + '()' if template == (self,) else describe(template)

    def __repr__(self) -> str:
        return f'<{type(self).__name__} {self.describe()}>'


class TemplateSubstitution(Substitution):
    """A template already built (a `Text`'s), handed to code that expects launch's list of
    substitutions (`DeclareLaunchArgument.default_value`)."""

    def __init__(self, template: Template) -> None:
        self._template = template

    def template(self) -> Template:
        return self._template


def to_template(value: Any) -> Template:
    """What launch calls SomeSubstitutionsType, as a template: a string (literal, never parsed
    for `$(...)`), a Substitution, or a list of them concatenated. Numbers and bools are
    accepted too (a bool as 'true' / 'false', the spelling conditions read).

    Raises:
        TypeError: anything else (the caller adds where it was written).
    """
    if isinstance(value, Text):
        return value.template
    if isinstance(value, str):
        return (value,) if value else ()
    if isinstance(value, Substitution):
        return value.template()
    if isinstance(value, bool):
        return ('true' if value else 'false',)
    if isinstance(value, (int, float)):
        return (str(value),)
    if isinstance(value, os.PathLike):
        return (os.fspath(value),)
    if isinstance(value, (list, tuple)):
        parts: list = []
        for item in value:
            parts.extend(to_template(item))
        return tuple(parts)
    raise TypeError(f'expected a string or a substitution, got {type(value).__name__}')


# -- deferred values kept by actions -----------------------------------------------------------
@dataclass(frozen=True)
class Text:
    """A string attribute: its template and where it was written."""

    template: Template
    origin: Origin

    @classmethod
    def parse(cls, text: str, origin: Origin) -> 'Text':
        """YAML: `text` is parsed for `$(...)` substitutions."""
        try:
            return cls(parse(text), origin)
        except SubstitutionError as exc:
            raise LaunchFileError(origin, str(exc)) from None

    @classmethod
    def of(cls, value: Any, origin: Origin) -> 'Text':
        """Python: a string, Substitution or list of them (see `to_template`); a Text as is."""
        if isinstance(value, Text):
            return value
        try:
            return cls(to_template(value), origin)
        except TypeError as exc:
            raise LaunchFileError(origin, str(exc)) from None

    def perform(self, context: SubstitutionContext) -> str:
        try:
            return perform(self.template, context)
        except SubstitutionError as exc:
            raise LaunchFileError(self.origin, str(exc)) from None

    def __str__(self) -> str:
        return describe(self.template)

    # -- launch's view: an action's text attribute is a list of substitutions ----------------
    def substitutions(self) -> list[Substitution]:
        """The template as launch keeps such a value (`action.msg[0].perform(context)`)."""
        from zros.launch.substitutions import substitutions_of
        return substitutions_of(self.template) or substitutions_of(('',))

    def __iter__(self) -> Any:
        return iter(self.substitutions())

    def __len__(self) -> int:
        return len(self.substitutions())

    def __getitem__(self, index: Any) -> Any:
        return self.substitutions()[index]

    def __bool__(self) -> bool:
        return True   # a value that was written, even if empty (not a container's emptiness)


@dataclass(frozen=True)
class Typed:
    """A bool / int / float attribute written either as a YAML value (`respawn: true`) or as a
    string that resolves to one (`respawn: $(var respawn)`); literal strings are checked when
    the file is parsed, resolved ones when they are evaluated."""

    data_type: type
    value: Any            # the constant, or a Text
    origin: Origin

    @classmethod
    def from_yaml(cls, value: Any, data_type: type, origin: Origin) -> 'Typed':
        if isinstance(value, str):
            text = Text.parse(value, origin)
            typed = cls(data_type, text, origin)
            if is_static(text.template):
                return cls(data_type, typed.convert(''.join(text.template)), origin)
            return typed
        return cls(data_type, cls(data_type, None, origin).convert(value), origin)

    @classmethod
    def of(cls, value: Any, data_type: type, origin: Origin) -> 'Typed':
        """Python: a bool / int / float, or a string / Substitution that resolves to one."""
        if isinstance(value, Typed):
            return value
        if isinstance(value, (bool, int, float)):
            return cls(data_type, cls(data_type, None, origin).convert(value), origin)
        text = Text.of(value, origin)
        if is_static(text.template):
            return cls(data_type, cls(data_type, None, origin).convert(''.join(text.template)), origin)
        return cls(data_type, text, origin)

    def convert(self, value: Any) -> Any:
        """`value` as `data_type`: text by launch's coercion rules
        (zros.launch.utilities.type_utils: 'on' is a bool, '1.' a float but no int), a value
        of the type as is (an int is also a float).

        Raises:
            LaunchFileError: it is not one, naming the expected type and what was given.
        """
        name = {bool: 'a bool (true or false)', int: 'an int', float: 'a number'}[self.data_type]
        if isinstance(value, str):
            from zros.launch.utilities.type_utils import coerce_to_type
            try:
                return coerce_to_type(value.strip(), self.data_type)
            except ValueError:
                pass
        elif self.data_type is bool:
            if isinstance(value, bool):
                return value
        elif isinstance(value, int if self.data_type is int else (int, float)) and not isinstance(value, bool):
            return self.data_type(value)
        shown = f' {value!r}' if not isinstance(value, (list, dict)) else ''
        kind = type(value).__name__ if not isinstance(value, str) else 'string'
        raise LaunchFileError(self.origin, f'expected {name}, got {kind}{shown}')

    def perform(self, context: SubstitutionContext) -> Any:
        if isinstance(self.value, Text):
            return self.convert(self.value.perform(context))
        return self.value

    def __str__(self) -> str:
        return str(self.value).lower() if isinstance(self.value, bool) else str(self.value)

    def substitutions(self) -> list[Substitution]:
        """launch's list-of-substitutions view (`action.sigterm_timeout[0].perform(context)`):
        a constant as its text, a substituted value as its Text's."""
        return self.value.substitutions() if isinstance(self.value, Text) else Text((str(self),), self.origin).substitutions()

    def __iter__(self) -> Any:
        return iter(self.substitutions())

    def __getitem__(self, index: Any) -> Any:
        return self.substitutions()[index]

    def launch_view(self) -> Any:
        """What launch's property for such an attribute returns: the constant (`timer.period`
        is 5.0, `executable.shell` is True), else the list of substitutions that give it."""
        return self.substitutions() if isinstance(self.value, Text) else self.value

    def __bool__(self) -> bool:
        """launch's view of such an attribute: the constant's truth (`if action.prepend:`), and
        true for one a substitution gives, as launch's non-empty list of substitutions is."""
        return True if isinstance(self.value, Text) else bool(self.value)


# -- the substitutions ------------------------------------------------------------------------
@dataclass(frozen=True)
class _Spec:
    function: Callable[[SubstitutionContext, list[str]], str]
    min_args: int
    max_args: int  # -1: any number
    summary: str
    frontend: bool = True    # written as $(name ...) in YAML; False: built by Python objects only
    lazy: bool = False       # the function gets `_Lazy` arguments and evaluates what it needs

    def arity_text(self) -> str:
        if self.max_args < 0:
            return f'at least {self.min_args} argument{"s" if self.min_args != 1 else ""}'
        if self.min_args == self.max_args:
            return f'{self.min_args} argument{"s" if self.min_args != 1 else ""}'
        return f'{self.min_args} to {self.max_args} arguments'


SUBSTITUTIONS: dict[str, _Spec] = {}


def substitution(*names: str, args: tuple[int, int], summary: str, frontend: bool = True,
                 lazy: bool = False):
    """Register a substitution function `f(context, evaluated_args) -> str` under `names`.

    `frontend=False` keeps it out of the YAML grammar (a Python-only substitution such as
    PathJoinSubstitution); `lazy=True` passes unevaluated arguments (see `_Lazy`)."""
    def register(function: Callable[[SubstitutionContext, list], str]):
        for name in names:
            SUBSTITUTIONS[name] = _Spec(function, args[0], args[1], summary, frontend, lazy)
        return function
    return register


_TRUE, _FALSE = ('true', '1'), ('false', '0')
#: A typed attribute (`prepend`, `scoped`, ...) also reads YAML 1.1's words, as launch's
#: typed substitutions do; conditions keep to `to_bool`'s four spellings.
_YAML_BOOLS = {'yes': True, 'on': True, 'no': False, 'off': False}


def to_bool(text: str) -> bool:
    """ROS 2's condition rule: 'true'/'1' and 'false'/'0', case-insensitive, nothing else."""
    value = str(text).strip().lower()
    if value in _TRUE:
        return True
    if value in _FALSE:
        return False
    raise SubstitutionError(f"'{text}' is not a boolean: use true, false, 1 or 0")


def _bool_text(value: bool) -> str:
    return 'true' if value else 'false'


@substitution('var', args=(1, 2), lazy=True,
              summary='a launch argument / configuration; the 2nd argument is a default')
def _var(context: SubstitutionContext, args: list[_Lazy]) -> str:
    name = args[0].value()
    note = getattr(context, 'note_configuration_read', None)
    if note is not None:
        note(name)
    if name in context.configurations:
        return context.configurations[name]
    if len(args) > 1:
        return args[1].value()
    known = ', '.join(sorted(context.configurations)) or 'none'
    raise SubstitutionError(f"launch configuration '{name}' is not set (set: {known})")


@substitution('env', args=(1, 2), lazy=True, summary='an environment variable; the 2nd argument is a default')
def _env(context: SubstitutionContext, args: list[_Lazy]) -> str:
    name = args[0].value()
    value = context.environment.get(name)
    if value is not None:
        return value
    if len(args) > 1:
        return args[1].value()
    raise SubstitutionError(f"environment variable '{name}' does not exist (give a default: "
                            f"$(env {name} DEFAULT))")


@substitution('optenv', args=(1, 2), lazy=True,
              summary='an environment variable, empty (or the default) when unset')
def _optenv(context: SubstitutionContext, args: list[_Lazy]) -> str:
    value = context.environment.get(args[0].value())
    if value is not None:
        return value
    return args[1].value() if len(args) > 1 else ''


@substitution('param', args=(1, 2), lazy=True,
              summary='a parameter set earlier with set_parameter (2nd argument: a default)')
def _param(context: SubstitutionContext, args: list[_Lazy]) -> str:
    name = args[0].value()
    for set_name, value in reversed(getattr(context, 'ros').param_pairs):
        if set_name == name:
            return _param_text(value)
    if len(args) > 1:
        return args[1].value()
    raise SubstitutionError(f"parameter '{name}' was not set with set_parameter")


def _param_text(value: Any) -> str:
    if isinstance(value, bool):
        return 'true' if value else 'false'
    if isinstance(value, (list, tuple)):
        return '[' + ', '.join(_param_text(v) for v in value) + ']'
    return str(value)


@substitution('path-join', args=(1, -1), frontend=False,
              summary='the arguments joined as one path (PathJoinSubstitution)')
def _path_join(context: SubstitutionContext, args: list[str]) -> str:
    return os.path.join(*args)


@substitution('dirname', args=(0, 0), summary='the directory of the current launch file')
def _dirname(context: SubstitutionContext, args: list[str]) -> str:
    if context.current_file:
        return os.path.dirname(os.path.abspath(context.current_file))
    return _launch_file_local(context, 'current_launch_file_directory')


@substitution('filename', args=(0, 0), summary='the path of the current launch file')
def _filename(context: SubstitutionContext, args: list[str]) -> str:
    if context.current_file:
        return os.path.abspath(context.current_file)
    return _launch_file_local(context, 'current_launch_file_path')


def _launch_file_local(context: SubstitutionContext, name: str) -> str:
    """Outside a file zros reads, the launch file is the local that launch's own include sets
    (`context.extend_locals({'current_launch_file_path': ...})`); with neither, it is an error
    rather than the working directory."""
    local = getattr(context, 'get_locals_as_dict', dict)().get(name)
    if not local:
        raise SubstitutionError(f'no current launch file: not in a launch file, and no {name} local')
    return str(local)


@substitution('find-pkg-share', args=(1, 1), summary="a package's share directory (see docs/packages.md)")
def _find_pkg_share(context: SubstitutionContext, args: list[str]) -> str:
    return str(_package_path(args[0]))


@substitution('find-pkg-prefix', args=(1, 1), summary="the directory that holds a package's share directory")
def _find_pkg_prefix(context: SubstitutionContext, args: list[str]) -> str:
    return str(_package_path(args[0]).parent)


def _package_path(package: str) -> Path:
    from zros.ament_index_python.packages import PackageNotFoundError, get_package_share_path
    try:
        return get_package_share_path(package)
    except PackageNotFoundError as exc:
        raise SubstitutionError(str(exc)) from None


@substitution('find-exec', args=(1, 1), summary='the full path of an executable on PATH')
def _find_exec(context: SubstitutionContext, args: list[str]) -> str:
    found = shutil.which(args[0], path=context.environment.get('PATH'))
    if found is None:
        raise SubstitutionError(f"executable '{args[0]}' not found on PATH")
    return found


@substitution('file-content', args=(1, 1), summary='the text of a file')
def _file_content(context: SubstitutionContext, args: list[str]) -> str:
    try:
        return Path(args[0]).read_text(encoding='utf-8')
    except FileNotFoundError:
        raise SubstitutionError(f'File not found: {args[0]}') from None   # launch's wording
    except OSError as exc:
        raise SubstitutionError(f"cannot read '{args[0]}': {exc.strerror}") from None


@substitution('log_dir', 'launch_log_dir', args=(0, 0), summary="this launch's log directory")
def _log_dir(context: SubstitutionContext, args: list[str]) -> str:
    if not context.log_dir:
        # a context made by hand (not by `zros launch`): as launch does, pick this launch's log
        # directory on first use and create it, so a file can be written there
        from zros.launch.supervisor import make_log_dir
        directory = make_log_dir(None)
        directory.mkdir(parents=True, exist_ok=True)
        context.log_dir = str(directory)
    return str(context.log_dir)


@substitution('anon', args=(1, 1), summary='a name made unique for this launch (same input, same output)')
def _anon(context: SubstitutionContext, args: list[str]) -> str:
    return context.anon_name(args[0])


def make_anon_name(name: str) -> str:
    """`name_<host>_<pid>_<random number>` (launch's form), valid as a ROS node name."""
    clean = re.sub(r'[^A-Za-z0-9_]', '_', f'{name}_{socket.gethostname()}')
    return f'{clean}_{os.getpid()}_{secrets.randbelow(2**63)}'


@substitution('command', args=(1, 2),
              summary="stdout of a command (timeout 10 s); 2nd argument: fail|ignore|warn|capture stderr")
def _command(context: SubstitutionContext, args: list[str]) -> str:
    on_stderr = args[1] if len(args) > 1 else 'fail'
    if on_stderr not in ('fail', 'ignore', 'warn', 'capture'):
        raise SubstitutionError(f"$(command): on_stderr must be fail, ignore, warn or capture, got '{on_stderr}'")
    try:
        argv = shlex.split(args[0])
    except ValueError as exc:
        raise SubstitutionError(f'$(command {args[0]!r}): {exc}') from None
    if not argv:
        raise SubstitutionError('$(command): empty command')
    try:
        result = subprocess.run(argv, capture_output=True, text=True, timeout=COMMAND_TIMEOUT_S,
                                env=dict(context.environment), stdin=subprocess.DEVNULL, check=False)
    except FileNotFoundError:
        raise SubstitutionError(f"$(command): file not found: '{argv[0]}'") from None
    except OSError as exc:   # not executable, a directory, ...
        raise SubstitutionError(f"$(command): cannot run '{argv[0]}': {exc.strerror}") from None
    except subprocess.TimeoutExpired:
        raise SubstitutionError(f'$(command {args[0]!r}) did not finish within {COMMAND_TIMEOUT_S:g} s') from None
    # launch's wording ("executed command failed. Command: ..."), which users and tests match
    stderr = result.stderr.strip()
    if result.returncode != 0:
        detail = stderr.splitlines()[-1:] or ['no stderr']
        raise SubstitutionError(f'$(command): executed command failed. Command: {args[0]} '
                                f'(exit code {result.returncode}: {detail[0]})')
    if stderr and on_stderr == 'fail':
        raise SubstitutionError(f'$(command): executed command showed stderr output. Command: {args[0]} '
                                f'(stderr: {stderr[:200]})')
    if stderr and on_stderr == 'warn':
        import sys
        print(f'[WARNING] [launch]: $(command {args[0]!r}) wrote to stderr: {stderr}', file=sys.stderr)
    # kept as printed, trailing newline too, as launch keeps it (a YAML-typed value ignores it)
    return result.stdout + (result.stderr if on_stderr == 'capture' else '')


@substitution('not', args=(1, 1), summary="'true' when the argument is false")
def _not(context: SubstitutionContext, args: list[str]) -> str:
    return _bool_text(not to_bool(args[0]))


@substitution('and', 'all', args=(2, -1), summary="'true' when every argument is true")
def _and(context: SubstitutionContext, args: list[str]) -> str:
    return _bool_text(all([to_bool(a) for a in args]))


@substitution('or', 'any', args=(2, -1), summary="'true' when any argument is true")
def _or(context: SubstitutionContext, args: list[str]) -> str:
    return _bool_text(any([to_bool(a) for a in args]))


def _is_float(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _equal(left: str, right: str) -> bool:
    """launch's equality: as bools when both are true/false/1/0 (any case), as numbers (within
    math.isclose, so 'nan' equals nothing) when both are numbers, else as text."""
    a, b = left.lower(), right.lower()
    if a in (*_TRUE, *_FALSE) and b in (*_TRUE, *_FALSE):
        return (a in _TRUE) == (b in _TRUE)
    if _is_float(left) and _is_float(right):
        return math.isclose(float(left), float(right))
    return left == right


@substitution('equals', args=(2, 2),
              summary="'true' when both arguments are equal (as bools, as numbers within isclose, or as text)")
def _equals(context: SubstitutionContext, args: list[str]) -> str:
    return _bool_text(_equal(args[0], args[1]))


@substitution('not-equals', args=(2, 2), summary="'true' when the arguments differ")
def _not_equals(context: SubstitutionContext, args: list[str]) -> str:
    return _bool_text(not _equal(args[0], args[1]))


@substitution('if', args=(2, 3), lazy=True,
              summary='the 2nd argument when the 1st is true (also yes/on), else the 3rd (or empty)')
def _if(context: SubstitutionContext, args: list[_Lazy]) -> str:
    # a typed bool, as launch's IfElseSubstitution reads it: YAML's yes/on/no/off too
    from zros.launch.utilities.type_utils import coerce_to_type
    try:
        condition = coerce_to_type(args[0].value().strip(), bool)
    except ValueError as exc:
        raise SubstitutionError(f'$(if): {exc}') from None
    if condition:
        return args[1].value()
    return args[2].value() if len(args) > 2 else ''


# -- $(eval): a Python expression, restricted --------------------------------------------------
_SAFE_BUILTINS = {
    name: getattr(builtins, name)
    for name in ('abs', 'all', 'any', 'bool', 'dict', 'divmod', 'float', 'int', 'len', 'list', 'max',
                 'min', 'pow', 'range', 'repr', 'reversed', 'round', 'set', 'sorted', 'str', 'sum',
                 'tuple', 'zip', 'True', 'False', 'None')
}
_MATH = {name: getattr(math, name) for name in dir(math) if not name.startswith('_')}
_FORBIDDEN_NODES = (ast.Lambda, ast.NamedExpr, ast.Await, ast.Yield, ast.YieldFrom)


def evaluate_expression(expression: str, modules: str | None = None) -> str:
    """Evaluate `expression` like launch's PythonExpression, in a restricted scope.

    Args:
        modules: the modules in scope, separated by commas or spaces, each under its name; math's
            names also without the `math.` prefix when math is one of them. None means 'math'
            (launch's default), '' none at all.

    Only harmless builtins exist, `true` and `false` are names too (launch arguments are spelled
    that way), and no name or attribute may start with '_' (which closes the usual escapes
    through `__class__` / `__globals__`).

    Raises:
        ExpressionNameError: the expression uses a name that is not in scope (also a NameError,
            as launch's is).
        SubstitutionError: any other problem: syntax, a forbidden name, a module that cannot be
            imported, an exception of the expression.
    """
    try:
        tree = ast.parse(expression.strip(), mode='eval')
    except SyntaxError as exc:
        raise SubstitutionError(f'$(eval {expression!r}): invalid Python expression: {exc.msg}') from None
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute) and node.attr.startswith('_'):
            raise SubstitutionError(f"$(eval {expression!r}): attribute '{node.attr}' is not allowed")
        if isinstance(node, ast.Name) and node.id.startswith('_'):
            raise SubstitutionError(f"$(eval {expression!r}): name '{node.id}' is not allowed")
        if isinstance(node, _FORBIDDEN_NODES):
            raise SubstitutionError(f'$(eval {expression!r}): {type(node).__name__.lower()} is not allowed')
    scope = {'__builtins__': _SAFE_BUILTINS, **_expression_modules(modules), 'true': True, 'false': False}
    try:
        result = eval(compile(tree, '<eval>', 'eval'), scope, {})  # noqa: S307 - restricted above
    except NameError as exc:
        raise ExpressionNameError(f'$(eval {expression!r}) failed: NameError: {exc}') from None
    except Exception as exc:  # noqa: BLE001 - any error of the user's expression is reported
        raise SubstitutionError(f'$(eval {expression!r}) failed: {type(exc).__name__}: {exc}') from None
    return str(result)


def _expression_modules(modules: str | None) -> dict[str, Any]:
    """The names `modules` (see evaluate_expression) put in an expression's scope."""
    scope: dict[str, Any] = {}
    for name in ('math' if modules is None else modules).replace(',', ' ').split():
        try:
            scope[name] = importlib.import_module(name)
        except ImportError as exc:
            raise SubstitutionError(f"$(eval): cannot import module '{name}': {exc}") from None
        if name == 'math':
            scope.update(_MATH)
    return scope


@substitution('eval', args=(1, 2),
              summary="a Python expression with math's names (2nd argument: the modules, 'math' by default)")
def _eval(context: SubstitutionContext, args: list[str]) -> str:
    return evaluate_expression(args[0], args[1] if len(args) > 1 else None)
