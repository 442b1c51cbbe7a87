"""zros's launch_yaml: YAML launch files are read by zros.launch itself (zros.launch.entity);
this package only gives Python launch files launch_yaml's name for the source class.

`from launch_yaml.launch_description_sources import YAMLLaunchDescriptionSource` works unchanged.
"""
from __future__ import annotations

from zros.launch_yaml import launch_description_sources

__all__ = ['launch_description_sources']
