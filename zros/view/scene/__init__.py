"""zros.view.scene: RViz's role in the browser, on viser.

`SceneView` serves the page; `load_config` reads `.rviz` files and zros view files; the message
conversion (`convert`), TF seam (`frames`), tools (`tools`), graph drawing (`graph_hides`,
`graph_layout`, `graph_svg`) and console filtering (`console`) are plain Python, tested without a browser. viser is imported only
when a view starts.
"""
from __future__ import annotations

from zros.view.scene.config import ConfigError, DisplayConfig, GridConfig, ViewConfig, dump_view, load_config

__all__ = ['SceneView', 'ViewError', 'DEFAULT_PORT', 'ConfigError', 'DisplayConfig', 'GridConfig', 'ViewConfig',
           'dump_view', 'load_config']


def __getattr__(name: str):
    if name in ('SceneView', 'ViewError', 'DEFAULT_PORT'):
        from zros.view.scene import app
        return getattr(app, name)
    raise AttributeError(name)
