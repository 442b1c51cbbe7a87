"""zros's launch_xml: XML launch files are read by zros.launch itself (zros.launch.xml_entity);
its `Parser` and `Entity` are the XML format of zros.launch.frontend, and its source class
lets a Python launch file include an XML one.

`from launch_xml.launch_description_sources import XMLLaunchDescriptionSource` works unchanged.
"""
from __future__ import annotations

from zros.launch.frontend.formats import XmlParser as Parser
from zros.launch.xml_entity import XmlEntity as Entity
from zros.launch_xml import launch_description_sources

__all__ = ['Entity', 'Parser', 'launch_description_sources']
