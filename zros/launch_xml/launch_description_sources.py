"""`XMLLaunchDescriptionSource`: a `.launch.xml` file to include from a Python launch file."""
from __future__ import annotations

from zros.launch.files import module_getattr
from zros.launch.launch_description_sources import FrontendLaunchDescriptionSource

__all__ = ['XMLLaunchDescriptionSource']

__getattr__ = module_getattr(__name__)


class XMLLaunchDescriptionSource(FrontendLaunchDescriptionSource):
    """A `.launch.xml` file (launch_xml's source): read as XML whatever its name."""

    kind = 'xml'
