"""Finding interface files and turning them into classes, on demand.

The search path is `ZROS_INTERFACE_PATH` (os.pathsep-separated directories laid out as
`<pkg>/{msg,srv,action}/*`), then the packages on `ZROS_NODE_PATH` and installed ones
(zros.ament_index_python.packages), then the interfaces shipped in the `interfaces` package.
A user's directory comes first so a project can carry its own copy of a package.
Classes are built once per process and cached; lookups are thread-safe.

A package may also be known under a second name (PACKAGE_ALIASES): both names give the very
same classes, so the type on the wire is one and code written for either name interoperates.
"""
from __future__ import annotations

import os
import threading
from pathlib import Path
from typing import Any

from interfaces import PACKAGE_ALIASES
from zros import idl
from zros.errors import InterfaceNotFoundError
from zros.message import make_action_class, make_message_class, make_service_class

__all__ = [
    'KINDS', 'search_roots', 'get_type', 'get_message', 'get_service', 'get_action',
    'list_packages', 'list_interfaces', 'interface_file', 'normalize_type_name', 'type_name_of',
    'PACKAGE_ALIASES',
]

KINDS = ('msg', 'srv', 'action')
_EXT = {'msg': '.msg', 'srv': '.srv', 'action': '.action'}
_BUILTIN_ROOT = Path(__file__).resolve().parent.parent / 'interfaces'


_lock = threading.RLock()
_cache: dict[str, Any] = {}


def search_roots() -> list[Path]:
    from zros.ament_index_python.packages import interface_roots
    roots = [Path(p) for p in os.environ.get('ZROS_INTERFACE_PATH', '').split(os.pathsep) if p]
    roots.extend(interface_roots())   # packages on ZROS_NODE_PATH and installed ones (docs/packages.md)
    try:
        import interfaces  # the installed package may live elsewhere than this checkout
        roots.extend(Path(p) for p in interfaces.__path__)
    except ImportError:
        roots.append(_BUILTIN_ROOT)
    seen, unique = set(), []
    for root in roots:
        key = root.resolve() if root.exists() else root
        if key not in seen:
            seen.add(key)
            unique.append(root)
    return unique


def interface_file(package: str, kind: str, name: str) -> Path | None:
    package = PACKAGE_ALIASES.get(package, package)
    for root in search_roots():
        path = root / package / kind / (name + _EXT[kind])
        if path.is_file():
            return path
    return None


def normalize_type_name(name: str) -> str:
    """'pkg/msg/Name' stays; 'pkg/Name' becomes the first of msg, srv, action that exists."""
    parts = name.strip().split('/')
    if parts[0] in PACKAGE_ALIASES:
        parts[0] = PACKAGE_ALIASES[parts[0]]
    if len(parts) == 3 and parts[1] in KINDS and all(parts):
        return '/'.join(parts)
    if len(parts) == 2 and all(parts):
        for kind in KINDS:
            base = parts[1]
            for suffix in ('_Request', '_Response', '_Event', '_Goal', '_Result', '_Feedback'):
                if base.endswith(suffix) and kind != 'msg':
                    base = base[:-len(suffix)]
            if interface_file(parts[0], kind, base):
                return f'{parts[0]}/{kind}/{parts[1]}'
        raise InterfaceNotFoundError(f"unknown interface type '{name}'")
    raise InterfaceNotFoundError(
        f"invalid interface type '{name}': expected 'package/msg/Name' (or /srv/, /action/)")


def type_name_of(obj: Any) -> str:
    """The 'pkg/kind/Name' of a message, service or action class or instance."""
    name = getattr(obj, '_TYPE', None)
    if not isinstance(name, str) or not name:
        raise TypeError(f'{obj!r} is not a zros interface type')
    return name


def _load_spec(package: str, kind: str, name: str) -> Any:
    path = interface_file(package, kind, name)
    if path is None:
        raise InterfaceNotFoundError(
            f"unknown interface type '{package}/{kind}/{name}' "
            f"(searched: {', '.join(str(r) for r in search_roots())})")
    return idl.parse_file(path)


def get_type(name: str) -> Any:
    """Return the class for 'pkg/msg/Name', 'pkg/srv/Name', 'pkg/action/Name' (or a part of
    one, such as 'pkg/srv/Name_Request'). Raises InterfaceNotFoundError / InterfaceParseError."""
    full = normalize_type_name(name)
    cls = _cache.get(full)
    if cls is not None:
        return cls
    with _lock:
        cls = _cache.get(full)
        if cls is None:
            cls = _build(full)
        return cls


def _build(full: str) -> Any:
    package, kind, name = full.split('/')
    if kind == 'msg':
        spec = _load_spec(package, kind, name)
        cls = make_message_class(spec, get_message)
    elif kind == 'srv':
        for suffix, attr in (('_Request', 'Request'), ('_Response', 'Response'), ('_Event', 'Event')):
            if name.endswith(suffix):
                cls = getattr(get_type(f'{package}/srv/{name[:-len(suffix)]}'), attr)
                _cache[full] = cls
                return cls
        spec = _load_spec(package, kind, name)
        cls = make_service_class(spec, _message_part(spec.request), _message_part(spec.response),
                                 event=lambda spec=spec: _message_part(idl.service_event_spec(spec)))
    else:
        for suffix in ('_Goal', '_Result', '_Feedback'):
            if name.endswith(suffix):
                cls = getattr(get_type(f'{package}/action/{name[:-len(suffix)]}'), suffix[1:])
                _cache[full] = cls
                return cls
        spec = _load_spec(package, kind, name)
        cls = make_action_class(spec, *[_message_part(s) for s in (spec.goal, spec.result, spec.feedback)])
    _cache[full] = cls
    return cls


def _message_part(spec: idl.MessageSpec) -> type:
    cls = make_message_class(spec, get_message)
    _cache[spec.full_name] = cls
    return cls


def get_message(name: str) -> type:
    cls = get_type(name)
    if not hasattr(cls, '_ENC'):
        raise InterfaceNotFoundError(f"'{name}' is not a message type")
    return cls


def get_service(name: str) -> type:
    cls = get_type(name)
    if not hasattr(cls, 'Request'):
        raise InterfaceNotFoundError(f"'{name}' is not a service type")
    return cls


def get_action(name: str) -> type:
    cls = get_type(name)
    if not hasattr(cls, 'Goal'):
        raise InterfaceNotFoundError(f"'{name}' is not an action type")
    return cls


def list_packages() -> list[str]:
    found = set()
    for root in search_roots():
        if root.is_dir():
            for pkg in root.iterdir():
                if pkg.is_dir() and any((pkg / k).is_dir() for k in KINDS):
                    found.add(pkg.name)
    found.update(alias for alias, package in PACKAGE_ALIASES.items() if package in found)
    return sorted(found)


def list_interfaces(package: str | None = None, kinds: tuple[str, ...] = KINDS) -> list[str]:
    """Every 'pkg/kind/Name' on the search path (first root wins on duplicates); an alias's
    interfaces are listed under the alias only when it is asked for by name."""
    if package in PACKAGE_ALIASES:
        return [f'{package}/{n.split("/", 1)[1]}' for n in list_interfaces(PACKAGE_ALIASES[package], kinds)]
    found = set()
    for root in search_roots():
        packages = [root / package] if package else (sorted(root.iterdir()) if root.is_dir() else [])
        for pkg in packages:
            for kind in kinds:
                folder = pkg / kind
                if folder.is_dir():
                    for f in folder.iterdir():
                        if f.suffix == _EXT[kind]:
                            found.add(f'{pkg.name}/{kind}/{f.stem}')
    return sorted(found)

