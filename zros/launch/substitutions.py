"""Substitutions: `$(name arg1 'arg 2' ...)` inside launch-file strings, nested freely.

The grammar is ROS 2's (launch/frontend/grammar.lark): outside a substitution everything is
literal text (`\\$` is a literal dollar); inside, arguments are separated by spaces and may be
quoted with `'` or `"` (quotes may hold spaces and further substitutions). Parsing happens when
the file is parsed, so an unknown substitution or a wrong argument count is reported with the
file, line, tag and key before anything runs; evaluation happens while the launch is resolved.

`Text` and `Typed` are the deferred values that actions keep: a parsed template plus where it
was written, so an evaluation error (`$(var missing)`) still names file:line, tag and key.
"""
from __future__ import annotations

import ast
import builtins
import math
import os
import re
import secrets
import shlex
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Protocol

from zros.launch.errors import LaunchFileError, Origin, SubstitutionError

__all__ = [
    'Call', 'Template', 'parse', 'perform', 'is_static', 'describe', 'Text', 'Typed',
    'SubstitutionContext', 'SUBSTITUTIONS', 'to_bool', 'evaluate_expression',
    'COMMAND_TIMEOUT_S',
]

#: `$(command ...)` is killed after this many seconds (a launch must never hang on it).
COMMAND_TIMEOUT_S = 10.0


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

    def fail(self, reason: str, at: int | None = None) -> SubstitutionError:
        col = (self.i if at is None else at) + 1
        return SubstitutionError(f'{reason} (column {col} of {self.s!r})')

    def starts_call(self) -> bool:
        return self.s.startswith('$(', self.i)

    def template(self) -> Template:
        parts: list = []
        buf: list[str] = []
        while self.i < self.n:
            if self.s.startswith('\\$', self.i):
                buf.append('$')
                self.i += 2
            elif self.starts_call():
                _flush(parts, buf)
                parts.append(self.call())
            else:
                buf.append(self.s[self.i])
                self.i += 1
        _flush(parts, buf)
        return tuple(parts)

    def call(self) -> Call:
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
        if spec is None:
            raise self.fail(f"unknown substitution '{name}' (known: {', '.join(sorted(SUBSTITUTIONS))})", start)
        if not spec.min_args <= len(args) <= (spec.max_args if spec.max_args >= 0 else len(args)):
            raise self.fail(f"'$({name})' takes {spec.arity_text()}, got {len(args)}", start)
        return Call(name, tuple(args))

    def argument(self) -> Template:
        parts: list = []
        buf: list[str] = []
        while self.i < self.n:
            char = self.s[self.i]
            if char in ' \t)':
                break
            if char in '\'"':
                self.quoted(char, parts, buf)
            elif self.starts_call():
                _flush(parts, buf)
                parts.append(self.call())
            elif char == '\\' and self.i + 1 < self.n:
                buf.append(self.s[self.i + 1])
                self.i += 2
            else:
                buf.append(char)
                self.i += 1
        _flush(parts, buf)
        return tuple(parts)

    def quoted(self, quote: str, parts: list, buf: list[str]) -> None:
        start = self.i
        self.i += 1
        while self.i < self.n:
            char = self.s[self.i]
            if char == quote:
                self.i += 1
                return
            if char == '\\' and self.i + 1 < self.n and self.s[self.i + 1] in (quote, '\\', '$'):
                buf.append(self.s[self.i + 1])
                self.i += 2
            elif self.starts_call():
                _flush(parts, buf)
                parts.append(self.call())
            else:
                buf.append(char)
                self.i += 1
        raise self.fail(f'unterminated {quote} quote', start)


def _flush(parts: list, buf: list[str]) -> None:
    if buf:
        parts.append(''.join(buf))
        buf.clear()


def parse(text: str) -> Template:
    """Parse a string into literal text and substitutions; SubstitutionError on bad syntax."""
    if '$' not in text:
        return (text,) if text else ()
    return _Parser(text).template()


def is_static(template: Template) -> bool:
    return all(isinstance(part, str) for part in template)


def describe(template: Template) -> str:
    """The template written back as text (for --show-args defaults and --print)."""
    out = []
    for part in template:
        if isinstance(part, str):
            out.append(part.replace('$(', '\\$('))
        else:
            args = ''.join(' ' + _describe_arg(arg) for arg in part.args)
            out.append(f'$({part.name}{args})')
    return ''.join(out)


def _describe_arg(arg: Template) -> str:
    text = describe(arg)
    if text and not any(c in text for c in ' \t()\'"'):
        return text
    quote = "'" if "'" not in text else '"'
    return quote + text.replace(quote, '\\' + quote) + quote


def perform(template: Template, context: SubstitutionContext) -> str:
    """Evaluate a template; SubstitutionError (without location) when a substitution fails."""
    out = []
    for part in template:
        if isinstance(part, str):
            out.append(part)
        else:
            spec = SUBSTITUTIONS[part.name]
            args = [perform(arg, context) for arg in part.args]
            out.append(spec.function(context, args))
    return ''.join(out)


# -- deferred values kept by actions -----------------------------------------------------------
@dataclass(frozen=True)
class Text:
    """A string attribute: its parsed template and where it was written."""

    template: Template
    origin: Origin

    @classmethod
    def parse(cls, text: str, origin: Origin) -> 'Text':
        try:
            return cls(parse(text), origin)
        except SubstitutionError as exc:
            raise LaunchFileError(origin, str(exc)) from None

    def perform(self, context: SubstitutionContext) -> str:
        try:
            return perform(self.template, context)
        except SubstitutionError as exc:
            raise LaunchFileError(self.origin, str(exc)) from None

    def __str__(self) -> str:
        return describe(self.template)


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

    def convert(self, value: Any) -> Any:
        name = {bool: 'a bool (true or false)', int: 'an int', float: 'a number'}[self.data_type]
        if self.data_type is bool:
            if isinstance(value, bool):
                return value
            if isinstance(value, str):
                try:
                    return to_bool(value)
                except SubstitutionError:
                    pass
        elif self.data_type is int:
            if isinstance(value, int) and not isinstance(value, bool):
                return value
            if isinstance(value, str):
                try:
                    return int(value.strip())
                except ValueError:
                    pass
        elif self.data_type is float:
            if isinstance(value, (int, float)) and not isinstance(value, bool):
                return float(value)
            if isinstance(value, str):
                try:
                    return float(value.strip())
                except ValueError:
                    pass
        shown = f' {value!r}' if not isinstance(value, (list, dict)) else ''
        kind = type(value).__name__ if not isinstance(value, str) else 'string'
        raise LaunchFileError(self.origin, f'expected {name}, got {kind}{shown}')

    def perform(self, context: SubstitutionContext) -> Any:
        if isinstance(self.value, Text):
            return self.convert(self.value.perform(context))
        return self.value

    def __str__(self) -> str:
        return str(self.value).lower() if isinstance(self.value, bool) else str(self.value)


# -- the substitutions ------------------------------------------------------------------------
@dataclass(frozen=True)
class _Spec:
    function: Callable[[SubstitutionContext, list[str]], str]
    min_args: int
    max_args: int  # -1: any number
    summary: str

    def arity_text(self) -> str:
        if self.max_args < 0:
            return f'at least {self.min_args} argument{"s" if self.min_args != 1 else ""}'
        if self.min_args == self.max_args:
            return f'{self.min_args} argument{"s" if self.min_args != 1 else ""}'
        return f'{self.min_args} to {self.max_args} arguments'


SUBSTITUTIONS: dict[str, _Spec] = {}


def substitution(*names: str, args: tuple[int, int], summary: str):
    """Register a substitution function `f(context, evaluated_args) -> str` under `names`."""
    def register(function: Callable[[SubstitutionContext, list[str]], str]):
        for name in names:
            SUBSTITUTIONS[name] = _Spec(function, args[0], args[1], summary)
        return function
    return register


_TRUE, _FALSE = ('true', '1'), ('false', '0')


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


@substitution('var', args=(1, 2), summary='a launch argument / configuration; the 2nd argument is a default')
def _var(context: SubstitutionContext, args: list[str]) -> str:
    name = args[0]
    if name in context.configurations:
        return context.configurations[name]
    if len(args) > 1:
        return args[1]
    known = ', '.join(sorted(context.configurations)) or 'none'
    raise SubstitutionError(f"launch configuration '{name}' is not set (set: {known})")


@substitution('env', args=(1, 2), summary='an environment variable; the 2nd argument is a default')
def _env(context: SubstitutionContext, args: list[str]) -> str:
    value = context.environment.get(args[0])
    if value is not None:
        return value
    if len(args) > 1:
        return args[1]
    raise SubstitutionError(f"environment variable '{args[0]}' is not set (give a default: "
                            f"$(env {args[0]} DEFAULT))")


@substitution('optenv', args=(1, 2), summary='an environment variable, empty (or the default) when unset')
def _optenv(context: SubstitutionContext, args: list[str]) -> str:
    return context.environment.get(args[0], args[1] if len(args) > 1 else '')


@substitution('dirname', args=(0, 0), summary='the directory of the current launch file')
def _dirname(context: SubstitutionContext, args: list[str]) -> str:
    return os.path.dirname(os.path.abspath(context.current_file))


@substitution('filename', args=(0, 0), summary='the path of the current launch file')
def _filename(context: SubstitutionContext, args: list[str]) -> str:
    return os.path.abspath(context.current_file)


@substitution('find-pkg-share', 'find-pkg-prefix', args=(1, 1),
              summary='the directory of a zros package (see docs/launch.md)')
def _find_pkg_share(context: SubstitutionContext, args: list[str]) -> str:
    from zros.launch.packages import PackageNotFoundError, package_share_directory
    try:
        return str(package_share_directory(args[0]))
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
    except OSError as exc:
        raise SubstitutionError(f"cannot read '{args[0]}': {exc.strerror}") from None


@substitution('log_dir', 'launch_log_dir', args=(0, 0), summary="this launch's log directory")
def _log_dir(context: SubstitutionContext, args: list[str]) -> str:
    return str(context.log_dir)


@substitution('anon', args=(1, 1), summary='a name made unique for this launch (same input, same output)')
def _anon(context: SubstitutionContext, args: list[str]) -> str:
    return context.anon_name(args[0])


def make_anon_name(name: str) -> str:
    """`name_<pid>_<random>`, valid as a ROS node name."""
    clean = re.sub(r'[^A-Za-z0-9_]', '_', name) or 'anon'
    return f'{clean}_{os.getpid()}_{secrets.token_hex(4)}'


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
        raise SubstitutionError(f"$(command): '{argv[0]}' not found") from None
    except subprocess.TimeoutExpired:
        raise SubstitutionError(f'$(command {args[0]!r}) did not finish within {COMMAND_TIMEOUT_S:g} s') from None
    if result.returncode != 0:
        detail = result.stderr.strip().splitlines()[-1:] or ['no stderr']
        raise SubstitutionError(f'$(command {args[0]!r}) failed with exit code {result.returncode}: {detail[0]}')
    if result.stderr and on_stderr == 'fail':
        raise SubstitutionError(f'$(command {args[0]!r}) wrote to stderr: {result.stderr.strip()[:200]}')
    if result.stderr and on_stderr == 'warn':
        import sys
        print(f'[WARNING] [launch]: $(command {args[0]!r}) wrote to stderr: {result.stderr.strip()}', file=sys.stderr)
    output = result.stdout + (result.stderr if on_stderr == 'capture' else '')
    return output.rstrip('\n')


@substitution('not', args=(1, 1), summary="'true' when the argument is false")
def _not(context: SubstitutionContext, args: list[str]) -> str:
    return _bool_text(not to_bool(args[0]))


@substitution('and', 'all', args=(2, -1), summary="'true' when every argument is true")
def _and(context: SubstitutionContext, args: list[str]) -> str:
    return _bool_text(all([to_bool(a) for a in args]))


@substitution('or', 'any', args=(2, -1), summary="'true' when any argument is true")
def _or(context: SubstitutionContext, args: list[str]) -> str:
    return _bool_text(any([to_bool(a) for a in args]))


def _comparable(text: str) -> Any:
    lowered = text.strip().lower()
    if lowered in ('true', 'false'):
        return lowered == 'true'
    try:
        return float(text)
    except ValueError:
        return text


def _equal(left: str, right: str) -> bool:
    a, b = _comparable(left), _comparable(right)
    if type(a) is not type(b):
        return left == right
    return a == b


@substitution('equals', args=(2, 2), summary="'true' when both arguments are equal (as bools, numbers or text)")
def _equals(context: SubstitutionContext, args: list[str]) -> str:
    return _bool_text(_equal(args[0], args[1]))


@substitution('not-equals', args=(2, 2), summary="'true' when the arguments differ")
def _not_equals(context: SubstitutionContext, args: list[str]) -> str:
    return _bool_text(not _equal(args[0], args[1]))


@substitution('if', args=(2, 3), summary='the 2nd argument when the 1st is true, else the 3rd (or empty)')
def _if(context: SubstitutionContext, args: list[str]) -> str:
    return args[1] if to_bool(args[0]) else (args[2] if len(args) > 2 else '')


# -- $(eval): a Python expression, restricted --------------------------------------------------
_SAFE_BUILTINS = {
    name: getattr(builtins, name)
    for name in ('abs', 'all', 'any', 'bool', 'dict', 'divmod', 'float', 'int', 'len', 'list', 'max',
                 'min', 'pow', 'range', 'repr', 'reversed', 'round', 'set', 'sorted', 'str', 'sum',
                 'tuple', 'zip', 'True', 'False', 'None')
}
_MATH = {name: getattr(math, name) for name in dir(math) if not name.startswith('_')}
_FORBIDDEN_NODES = (ast.Lambda, ast.NamedExpr, ast.Await, ast.Yield, ast.YieldFrom)


def evaluate_expression(expression: str, modules: str = '') -> str:
    """Evaluate `expression` like launch's PythonExpression: `math`'s names are in scope (also
    as `math.x`), as are `true` and `false`; only harmless builtins exist, and no name or
    attribute may start with '_' (which closes the usual escapes through `__class__` /
    `__globals__`)."""
    for module in modules.replace(',', ' ').split():
        if module != 'math':
            raise SubstitutionError(f"$(eval): only the 'math' module is available, not '{module}'")
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
    # `true` / `false` too: launch arguments are usually spelled that way.
    scope = {'__builtins__': _SAFE_BUILTINS, 'math': math, **_MATH, 'true': True, 'false': False}
    try:
        result = eval(compile(tree, '<eval>', 'eval'), scope, {})  # noqa: S307 - restricted above
    except Exception as exc:  # noqa: BLE001 - any error of the user's expression is reported
        raise SubstitutionError(f'$(eval {expression!r}) failed: {type(exc).__name__}: {exc}') from None
    return str(result)


@substitution('eval', args=(1, 2), summary="a Python expression with math's names (2nd argument: 'math')")
def _eval(context: SubstitutionContext, args: list[str]) -> str:
    return evaluate_expression(args[0], args[1] if len(args) > 1 else '')
