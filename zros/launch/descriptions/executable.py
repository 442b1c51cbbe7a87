"""`Executable` (launch.descriptions.Executable): the program a process action runs, that is
its command line, launch prefix, name, working directory and environment, as written and,
after `prepare(context, action)`, as resolved.

ExecuteLocal (and so ExecuteProcess and Node) run an Executable; everything here is
resolution only: nothing is started and no path is checked.
"""
from __future__ import annotations

import os
import re
import shlex
from typing import Any, NamedTuple

from zros.launch.errors import LaunchFileError, Origin
from zros.launch.origin import origin_here
from zros.launch.template import Text

__all__ = ['Executable', 'CommandLine', 'split_arguments', 'environment_pairs', 'full_environment']


def split_arguments(text: str, origin: Origin) -> list[str]:
    """`text` split like a shell would (quotes group, no expansion)."""
    try:
        return shlex.split(text)
    except ValueError as exc:
        raise LaunchFileError(origin, f'cannot split {text!r} into arguments: {exc}') from None


class CommandLine(NamedTuple):
    """Arguments as written: YAML gives one string split like a shell would after substitution
    (`split=True`); Python gives a list whose items are one argument each."""

    parts: tuple[Text, ...]
    split: bool
    origin: Origin

    @classmethod
    def of(cls, value: Any, origin: Origin) -> 'CommandLine':
        """Python: a list of SomeSubstitutionsType (one argument each); a bare string is split."""
        if isinstance(value, CommandLine):
            return value
        if isinstance(value, (str, Text)):
            return cls((Text.of(value, origin),), True, origin)
        try:
            items = list(value)
        except TypeError:
            raise LaunchFileError(origin, f'expected a list of arguments, got {type(value).__name__}') from None
        return cls(tuple(Text.of(item, origin) for item in items), False, origin)

    @classmethod
    def yaml(cls, text: Text | None) -> 'CommandLine | None':
        return None if text is None else cls((text,), True, text.origin)

    def extended(self, more: 'CommandLine') -> 'CommandLine':
        """This line followed by `more` (Executable's `arguments`), each keeping how it splits."""
        if self.split == more.split:
            return CommandLine(self.parts + more.parts, self.split, self.origin)
        return CommandLine(self.as_arguments() + more.as_arguments(), False, self.origin)

    def perform(self, context: Any) -> list[str]:
        out: list[str] = []
        for part in self.parts:
            text = part.perform(context)
            if self.split:
                out += split_arguments(text, part.origin)
            else:
                out.append(text)
        return out

    def joined(self, context: Any) -> str:
        """The command line as one string (for `shell=True`)."""
        return ' '.join(part.perform(context) for part in self.parts)

    def as_arguments(self) -> tuple[Text, ...]:
        """One Text per argument, as launch keeps a command (`action.cmd[i][0].perform(...)`):
        a split line is cut at the whitespace of its literal text, a substitution staying with
        the text around it. Only a view: resolution splits the substituted text instead."""
        if not self.split:
            return self.parts
        arguments: list[Text] = []
        for part in self.parts:
            current: list[Any] = []
            for piece in part.template:
                if not isinstance(piece, str):
                    current.append(piece)
                    continue
                words = re.split(r'(\s+)', piece)
                for word in words:
                    if word.isspace():
                        if current:
                            arguments.append(Text(tuple(current), part.origin))
                        current = []
                    elif word:
                        current.append(word)
            if current:
                arguments.append(Text(tuple(current), part.origin))
        return tuple(arguments)


def environment_pairs(values: Any, origin: Origin) -> list[tuple[Text, Text]]:
    """`{name: value}` or `[(name, value)]` (each a SomeSubstitutionsType) as Text pairs."""
    items = values.items() if isinstance(values, dict) else values
    return [(Text.of(name, origin), Text.of(value, origin)) for name, value in items]


def full_environment(context: Any, changes: Any) -> dict[str, str]:
    """The launch's starting environment with `changes` ({name: value or None to unset}, or
    its items) made."""
    merged = {**context.base_environment, **dict(changes)}
    return {name: value for name, value in merged.items() if value is not None}


class Executable:
    """`Executable(cmd=[...], prefix, name, cwd, env, additional_env, arguments)`.

    Args:
        cmd: the program and its arguments, one SomeSubstitutionsType per argument (a bare
            string is split like a shell would).
        prefix: words put before the command (gdb, valgrind); without one, the
            `launch-prefix` launch configuration is, for programs whose name matches the
            `launch-prefix-filter` configuration (a regular expression; empty matches all).
        name: the process's label (default: the program's file name).
        cwd: the working directory.
        env: the whole environment of the process; None: the launch's environment.
        additional_env: variables set on top of either.
        arguments: more arguments after `cmd`.

    `prepare(context, action)` resolves these into `final_cmd`, `final_name`, `final_cwd` and
    `final_env` (the complete environment).
    """

    def __init__(self, *, cmd: Any = None, prefix: Any = None, name: Any = None, cwd: Any = None, env: Any = None,
                 additional_env: Any = None, arguments: Any = None, origin: Origin | None = None) -> None:
        self.origin = origin or origin_here('Executable')
        self.command = CommandLine.of(cmd, self.origin.with_key('cmd')) if cmd is not None else None
        if arguments is not None:
            more = CommandLine.of(arguments, self.origin.with_key('arguments'))
            self.command = more if self.command is None else self.command.extended(more)
        self.prefix_line = prefix if isinstance(prefix, CommandLine) or prefix is None else CommandLine(
            (Text.of(prefix, self.origin.with_key('prefix')),), True, self.origin.with_key('prefix'))
        self.name = None if name is None else Text.of(name, self.origin.with_key('name'))
        self.cwd = None if cwd is None else Text.of(cwd, self.origin.with_key('cwd'))
        self.env = None if env is None else environment_pairs(env, self.origin.with_key('env'))
        self.additional_env = environment_pairs(additional_env or [], self.origin.with_key('additional_env'))
        self.final_cmd: list[str] | None = None
        self.final_program = ''     # the program's word of final_cmd (after any prefix)
        self.final_name: str | None = None
        self.final_cwd: str | None = None
        self.final_env: dict[str, str] | None = None

    # -- launch's view of what was written ------------------------------------------------------
    @property
    def cmd(self) -> list[Text]:
        """The command, one list of substitutions per argument."""
        return list(self.command.as_arguments()) if self.command is not None else []

    @property
    def prefix(self) -> Text | None:
        return None if self.prefix_line is None else Text(
            tuple(p for part in self.prefix_line.parts for p in part.template), self.prefix_line.origin)

    # -- resolution -----------------------------------------------------------------------------
    def prefix_args(self, context: Any, program: str) -> list[str]:
        """The prefix for `program`: the one given, else the `launch-prefix` configuration when
        `program`'s file name matches `launch-prefix-filter`."""
        if self.prefix_line is not None:
            return self.prefix_line.perform(context)
        configured = context.configurations.get('launch-prefix', '')
        if not configured:
            return []
        pattern = context.configurations.get('launch-prefix-filter', '')
        try:
            wanted = re.match(pattern, os.path.basename(program)) is not None
        except re.error as exc:
            raise LaunchFileError(self.origin, f"launch configuration 'launch-prefix-filter' {pattern!r} "
                                               f'is no regular expression: {exc}') from None
        return split_arguments(configured, self.origin) if wanted else []

    def environment_changes(self, context: Any) -> dict[str, str | None]:
        """How the process's environment differs from the launch's starting one (None: unset)."""
        changes = dict(context.environment_changes())
        if self.env is not None:   # `env=`: the process gets exactly this environment
            wanted = {name.perform(context): value.perform(context) for name, value in self.env}
            inherited = set(os.environ) | set(context.base_environment)
            changes = {name: None for name in inherited if name not in wanted}
            changes.update(wanted)
        for name, value in self.additional_env:
            changes[name.perform(context)] = value.perform(context)
        return changes

    def label(self, context: Any, program: str) -> str:
        """The name given, else `program`'s file name."""
        return self.name.perform(context) if self.name is not None else os.path.basename(program)

    def prepare(self, context: Any, action: Any = None, *, shell: bool = False) -> None:
        """Resolve the `final_*` values in `context` (`action`, the one running this, is for
        subclasses). With `shell`, the command is one line for /bin/sh, not split."""
        if self.command is None:
            raise LaunchFileError(self.origin, "an executable needs 'cmd'")
        if shell:
            text = self.command.joined(context)
            first = (text.split() or ['sh'])[0]
            argv = ['/bin/sh', '-c', text]
        else:
            argv = self.command.perform(context)
            first = argv[0] if argv else ''
        if not (text.strip() if shell else argv):
            raise LaunchFileError(self.command.origin, 'empty command')
        self.final_program = first
        self.final_cmd = [*self.prefix_args(context, first), *argv]
        self.final_name = self.label(context, first)
        self.final_cwd = self.cwd.perform(context) if self.cwd is not None else None
        self.final_env = full_environment(context, self.environment_changes(context))
