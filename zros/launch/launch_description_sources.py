"""Where an included launch description comes from (launch.launch_description_sources).

A source is a launch description already built (`LaunchDescriptionSource(description)`, launch's
base class) or a launch file to read: a location (a path, possibly built from substitutions) and
a front end. Python, YAML and XML files may include each other freely;
`AnyLaunchDescriptionSource` and `FrontendLaunchDescriptionSource` pick the front end from the
file name (launch_xml's `XMLLaunchDescriptionSource` is in zros.launch_xml).
"""
from __future__ import annotations

from typing import Any

from zros.launch.errors import LaunchError, Origin
from zros.launch.files import (InvalidPythonLaunchFileError, get_launch_description_from_python_launch_file,
                               load_launch_description, load_python_launch_file_as_module, module_getattr)
from zros.launch.origin import origin_here
from zros.launch.template import Text, describe

__all__ = ['LaunchDescriptionSource', 'PythonLaunchDescriptionSource', 'FrontendLaunchDescriptionSource',
           'YAMLLaunchDescriptionSource', 'AnyLaunchDescriptionSource', 'LaunchFileSource', 'InvalidPythonLaunchFileError',
           'load_python_launch_file_as_module', 'get_launch_description_from_python_launch_file']

__getattr__ = module_getattr(__name__)


class LaunchDescriptionSource:
    """A launch description, where it comes from and how it was made (launch's base class).

    Args:
        launch_description: the description itself, when it was built in Python; None for a
            file, which `get_launch_description` reads when the include runs.
        location: where it comes from (str / Substitution / list): a file's path, or a label
            such as '<script>'.
        method: how it was made, for messages ('interpreted python launch file', ...).
    """

    #: the front end that reads the file: 'python', 'yaml', 'xml', or None to pick by file name
    kind: str | None = None

    def __init__(self, launch_description: Any = None, location: Any = '<string>',
                 method: str = 'unspecified mechanism from a script', *, origin: Origin | None = None) -> None:
        self.origin = origin or origin_here(type(self).__name__)
        self._launch_description = launch_description
        self.location_text = Text.of(location, self.origin.with_key('launch_file_path'))
        self._expanded_location: str | None = None
        self._read: tuple[str, Any] | None = None   # (path, description) of the file read last
        self.method = method

    @property
    def location(self) -> str:
        """The location as text: the path once `get_launch_description` has evaluated it, the
        location as written before."""
        return describe(self.location_text.template) if self._expanded_location is None else self._expanded_location

    def get_launch_description(self, context: Any, location: str | None = None) -> Any:
        """The LaunchDescription, read from the file the first time (`location`: the path
        already evaluated, else the location is evaluated in `context` once).

        Raises:
            LaunchError: a base source without a description (a RuntimeError, as launch's).
            LaunchFileError: the file is missing or wrong (LaunchFileNotFoundError,
                InvalidPythonLaunchFileError, ...).
        """
        if location is None:
            location = self._expanded_location or self.location_text.perform(context)
        self._expanded_location = location
        if self._launch_description is not None:
            return self._launch_description
        if self._read is None or self._read[0] != location:   # a relative path read from elsewhere
            self._read = (location, self._load(location))
        return self._read[1]

    def try_get_launch_description_without_context(self) -> Any:
        """The description if it can be had without a launch running (a file whose path needs
        no launch configuration), else None: for `--show-args`-like walks."""
        if self._launch_description is not None:
            return self._launch_description
        from zros.launch.context import LaunchContext
        try:
            return self._load(self.location_text.perform(LaunchContext()))
        except LaunchError:
            return None

    def _load(self, location: str) -> Any:
        raise LaunchError(f'{type(self).__name__}.get_launch_description(): no launch description was given '
                          f'(location {location!r})')

    def __repr__(self) -> str:
        return f'<{type(self).__name__} {self.location}>'


class LaunchFileSource(LaunchDescriptionSource):
    """A launch file read by the front end `kind` names (None: by the file name)."""

    method_text = 'interpreted launch file'

    def __init__(self, launch_file_path: Any, *, origin: Origin | None = None) -> None:
        super().__init__(None, launch_file_path, self.method_text,
                         origin=origin or origin_here(type(self).__name__))

    def _load(self, location: str) -> Any:
        return load_launch_description(location, self.kind)


class PythonLaunchDescriptionSource(LaunchFileSource):
    """A `.launch.py` file (its `generate_launch_description()`)."""

    kind = 'python'
    method_text = 'interpreted python launch file'


class FrontendLaunchDescriptionSource(LaunchFileSource):
    """A markup launch file, YAML or XML by its name (`.xml` / `.launch` is XML)."""

    method_text = 'interpreted frontend launch file'


class YAMLLaunchDescriptionSource(FrontendLaunchDescriptionSource):
    """A `.launch.yaml` file (launch_yaml's source)."""

    kind = 'yaml'


class AnyLaunchDescriptionSource(LaunchFileSource):
    """Python, YAML or XML, by the file name (`.py` is Python, `.xml` XML)."""
