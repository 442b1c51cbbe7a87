"""zros's launch_yaml: YAML launch files are read by zros.launch itself (zros.launch.entity);
its `Parser` and `Entity` are the YAML format of zros.launch.frontend, and its source class
lets a Python launch file include a YAML one.

`from launch_yaml.launch_description_sources import YAMLLaunchDescriptionSource` works unchanged.
"""
from __future__ import annotations

from zros.launch.frontend.formats import YamlParser as Parser
from zros.launch.entity import Entity as Entity
from zros.launch_yaml import launch_description_sources

__all__ = ['Entity', 'Parser', 'launch_description_sources']
