"""`YAMLLaunchDescriptionSource` under launch_yaml's module name (the class is zros.launch's)."""
from __future__ import annotations

from zros.launch.files import module_getattr
from zros.launch.launch_description_sources import YAMLLaunchDescriptionSource

__all__ = ['YAMLLaunchDescriptionSource']

__getattr__ = module_getattr(__name__)
