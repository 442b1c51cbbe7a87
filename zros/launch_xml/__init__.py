"""zros's launch_xml: XML launch files are read by zros.launch itself (zros.launch.xml_entity);
this package only gives Python launch files launch_xml's source class to include one.

`from launch_xml.launch_description_sources import XMLLaunchDescriptionSource` works unchanged.
"""
from __future__ import annotations

from zros.launch_xml import launch_description_sources

__all__ = ['launch_description_sources']
