"""launch.frontend: the parser that XML and YAML launch files share, and how tags are added.

`Parser.load(file)` reads a markup launch file (by name, or trying each format) into its root
`Entity` and the parser for it; `parser.parse_description(root)` gives the `LaunchDescription`.
`@expose_action('tag')` on a class with `parse(entity, parser)` adds a tag for every front end
and for `zros launch`; a package makes its module load first by declaring it under the
`launch.frontend.launch_extension` entry point group, as for ROS 2's launch.
"""
from __future__ import annotations

from zros.launch.frontend.entity import Entity
from zros.launch.frontend import type_utils
from zros.launch.frontend.expose import expose_action, expose_substitution
from zros.launch.frontend.parser import InvalidFrontendLaunchFileError, Parser

__all__ = ['Entity', 'InvalidFrontendLaunchFileError', 'Parser', 'expose_action', 'expose_substitution',
           'type_utils']
