"""Where an included launch description comes from (launch.launch_description_sources).

A source is a location (a path, possibly built from substitutions) and a front end. Python, YAML
and XML files may include each other freely; `AnyLaunchDescriptionSource` and
`FrontendLaunchDescriptionSource` pick the front end from the file name (launch_xml's
`XMLLaunchDescriptionSource` is in zros.launch_xml).
"""
from __future__ import annotations

from typing import Any

from zros.launch.errors import Origin
from zros.launch.files import module_getattr
from zros.launch.origin import origin_here
from zros.launch.template import Text

__all__ = ['LaunchDescriptionSource', 'PythonLaunchDescriptionSource', 'FrontendLaunchDescriptionSource',
           'YAMLLaunchDescriptionSource', 'AnyLaunchDescriptionSource']

__getattr__ = module_getattr(__name__)


class LaunchDescriptionSource:
    """A launch file to include: `location` (str / Substitution / list) and a front end
    ('python', 'yaml', 'xml', or None to pick by file name)."""

    kind: str | None = None

    def __init__(self, launch_file_path: Any, *, origin: Origin | None = None) -> None:
        self.origin = origin or origin_here(type(self).__name__)
        self.location = Text.of(launch_file_path, self.origin.with_key('launch_file_path'))

    def __repr__(self) -> str:
        return f'<{type(self).__name__} {self.location}>'


class PythonLaunchDescriptionSource(LaunchDescriptionSource):
    """A `.launch.py` file (its `generate_launch_description()`)."""

    kind = 'python'


class FrontendLaunchDescriptionSource(LaunchDescriptionSource):
    """A markup launch file, YAML or XML by its name (`.xml` / `.launch` is XML)."""


class YAMLLaunchDescriptionSource(FrontendLaunchDescriptionSource):
    """A `.launch.yaml` file (launch_yaml's source)."""

    kind = 'yaml'


class AnyLaunchDescriptionSource(LaunchDescriptionSource):
    """Python, YAML or XML, by the file name (`.py` is Python, `.xml` XML)."""
