"""Combining namespaces the way launch_ros pushes them (launch_ros.utilities.namespace_utils
re-exports these; they live in the launch, which builds LoadNode requests with them).

Unlike zros.launch's `join_namespace` (which the resolver uses and which always answers an
absolute namespace), these keep a relative namespace relative: launch_ros composes a node's
namespace with its pushed one before it makes the result absolute.
"""
from __future__ import annotations

__all__ = ['is_root_namespace', 'is_namespace_absolute', 'prefix_namespace', 'make_namespace_absolute']


def is_root_namespace(ns: str) -> bool:
    """Whether `ns` is '/'."""
    return ns == '/'


def is_namespace_absolute(ns: str) -> bool:
    """Whether `ns` starts with '/'."""
    return ns.startswith('/')


def prefix_namespace(base_ns: str | None, ns: str | None) -> str | None:
    """`ns` under `base_ns` when `ns` is relative, `ns` itself when it is absolute.

    Either may be None (meaning "not given"): the other is the answer, and None if both are.
    An empty `base_ns` leaves `ns` as is. Trailing '/' are dropped, except from the root '/'.

    Examples: ('a', 'b') -> 'a/b'; ('/a', 'b') -> '/a/b'; ('a', '/b') -> '/b'; ('/', 'b') -> '/b'.
    """
    if ns is None:
        combined = base_ns
    elif not base_ns or is_namespace_absolute(ns):
        combined = ns
    else:
        combined = ('' if is_root_namespace(base_ns) else base_ns) + '/' + ns
    if combined is None or is_root_namespace(combined):
        return combined
    return combined.rstrip('/')


def make_namespace_absolute(ns: str | None) -> str | None:
    """`ns` with a leading '/' ('' becomes '/'); None stays None."""
    if ns is None or is_namespace_absolute(ns):
        return ns
    return '/' + ns
