"""launch.substitutions.launch_configuration: launch's module path of `LaunchConfiguration`, which
zros keeps in zros.launch.substitutions (one class, whichever path imported it)."""
from __future__ import annotations

from zros.launch.substitutions import LaunchConfiguration

__all__ = ['LaunchConfiguration']
