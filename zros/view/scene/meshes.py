"""Mesh files named by markers and URDF visuals (`file://`, `package://` or a plain path), loaded
with trimesh (a dependency of viser) and cached, since a robot model names each file once per
link and a marker array may name the same file hundreds of times."""
from __future__ import annotations

import functools
from typing import Any

__all__ = ['load_mesh']


@functools.lru_cache(maxsize=64)
def load_mesh(resource: str) -> Any:
    """A trimesh.Trimesh of the file (scenes flattened into one mesh).

    Raises:
        OSError: the file cannot be found or read as a mesh.
    """
    import trimesh

    from zros.urdf import resolve_package_uri
    try:
        path = resolve_package_uri(resource)
    except Exception as exc:  # noqa: BLE001 - an unknown package reads the same as a missing file
        raise OSError(f'cannot load {resource}: {exc}') from None
    if not path.is_file():
        raise OSError(f'cannot load {resource}: no such file {path}')
    try:
        loaded = trimesh.load(str(path), force='mesh')
    except Exception as exc:  # noqa: BLE001 - trimesh raises many kinds for a bad file
        raise OSError(f'cannot load {resource}: {exc}') from None
    if not hasattr(loaded, 'faces') or len(loaded.faces) == 0:
        raise OSError(f'cannot load {resource}: no triangles in it')
    return loaded
