"""launch.frontend.entity's `Entity`, under launch's module name: zros's entity class (the YAML
one; the XML entity derives from it), as extensions import it."""
from __future__ import annotations

from zros.launch.entity import Entity

__all__ = ['Entity']
