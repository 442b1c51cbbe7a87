"""`--ros-args` command-line arguments, understood by every node (ros2's syntax).

    --ros-args -r from:=to -r __node:=name -r __ns:=/ns -p name:=value
               --params-file f.yaml --log-level [logger:=]debug [--]
"""
from __future__ import annotations

import argparse
from dataclasses import dataclass, field

from zros.errors import CliError, RCLError

__all__ = ['RosArgs', 'parse_ros_args', 'remove_ros_args', 'RosArgsError', 'UnknownRosArgsError',
           'NodeArgumentParser']


class RosArgsError(RCLError, ValueError):
    """Malformed `--ros-args` section (rclpy's `RCLInvalidROSArgsError`); the message starts as
    rcl's does, 'Failed to parse ROS arguments: '."""

    def __init__(self, detail: str) -> None:
        super().__init__(f'Failed to parse ROS arguments: {detail}')


class UnknownRosArgsError(RosArgsError):
    """A `--ros-args` section holds arguments ROS does not know; the message lists them all, as
    `['unknown']`, so that one run shows every typo (rclpy's `UnknownROSArgsError`)."""


@dataclass
class RosArgs:
    remaps: list[str] = field(default_factory=list)
    params: list[tuple[str, str]] = field(default_factory=list)      # (name, yaml text)
    params_files: list[str] = field(default_factory=list)
    #: `-p` values and `--params-file` paths in command-line order, as rcl applies them (a later
    #: one wins): a (name, yaml text) pair is a `-p`, a str a parameter file.
    parameter_sources: list[tuple[str, str] | str] = field(default_factory=list)
    log_levels: list[tuple[str, str]] = field(default_factory=list)  # (logger or '', level)
    enclave: str | None = None
    disable_rosout: bool = False


_FLAGS_WITH_VALUE = {'-r', '--remap', '-p', '--param', '--params-file', '--log-level', '-e', '--enclave',
                     '--log-file-name', '--log-config-file'}
_FLAGS = {'--disable-rosout-logs', '--enable-rosout-logs', '--disable-stdout-logs', '--enable-stdout-logs',
          '--disable-external-lib-logs', '--enable-external-lib-logs'}


def _sections(argv: list[str]) -> tuple[list[str], list[list[str]]]:
    """Split argv into user arguments and the contents of each --ros-args section."""
    user, sections, current = [], [], None
    for arg in argv:
        if current is None:
            if arg == '--ros-args':
                current = []
                sections.append(current)
            else:
                user.append(arg)
        elif arg == '--':
            current = None
        elif arg == '--ros-args':
            current = []
            sections.append(current)
        else:
            current.append(arg)
    return user, sections


def remove_ros_args(args: list[str] | None) -> list[str]:
    """argv without any `--ros-args ... [--]` section (rclpy.utilities.remove_ros_args)."""
    import sys
    return _sections(list(sys.argv if args is None else args))[0]


def parse_ros_args(argv: list[str]) -> RosArgs:
    """Parse every `--ros-args` section of argv; raise RosArgsError naming the bad argument."""
    result = RosArgs()
    unknown: list[str] = []
    for section in _sections(argv)[1]:
        i = 0
        while i < len(section):
            flag = section[i]
            if flag in _FLAGS:
                result.disable_rosout |= flag == '--disable-rosout-logs'
                i += 1
                continue
            if flag not in _FLAGS_WITH_VALUE:
                unknown.append(flag)
                i += 1
                continue
            if i + 1 >= len(section):
                raise RosArgsError(f"ROS argument '{flag}' needs a value")
            value = section[i + 1]
            i += 2
            if flag in ('-r', '--remap'):
                if ':=' not in value:
                    raise RosArgsError(f"remapping '{value}' must look like from:=to")
                result.remaps.append(value)
            elif flag in ('-p', '--param'):
                if ':=' not in value:
                    raise RosArgsError(f"parameter '{value}' must look like name:=value")
                name, text = value.split(':=', 1)
                if not name:
                    raise RosArgsError(f"parameter '{value}' has no name")
                result.params.append((name, text))
                result.parameter_sources.append((name, text))
            elif flag == '--params-file':
                result.params_files.append(value)
                result.parameter_sources.append(value)
            elif flag == '--log-level':
                logger, _, level = value.rpartition(':=')
                result.log_levels.append((logger, level))
            elif flag in ('-e', '--enclave'):
                result.enclave = value
    if unknown:
        raise UnknownRosArgsError(f'unknown ROS arguments: {unknown}')
    return result


class NodeArgumentParser(argparse.ArgumentParser):
    """The parser of a node's own options (what `remove_ros_args` leaves: gazebo_ros's gzserver
    and spawn_entity.py): a bad command line is one CliError line, not argparse's usage block."""

    def error(self, message: str) -> None:   # type: ignore[override]
        raise CliError(f'{self.prog}: {message} (see {self.prog} -h)')
