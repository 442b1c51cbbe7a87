"""ROS 2 names: validation, expansion and remapping.

Names become Zenoh key expressions, so a name that slipped past validation could inject
wildcards (`*`, `**`, `$*`) into a key and subscribe to far more than it meant to. Every name
goes through `expand_topic_name` / `validate_*` before it reaches `zros.keys`.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field

from zros.errors import (InvalidNameError, InvalidNamespaceException, InvalidNodeNameException,
                         InvalidServiceNameException, InvalidTopicNameException)

__all__ = [
    'validate_node_name',
    'validate_namespace',
    'validate_full_name',
    'expand_topic_name',
    'normalize_namespace',
    'fully_qualified_node_name',
    'Remappings',
]

_KINDS = {'node name': InvalidNodeNameException, 'namespace': InvalidNamespaceException,
          'topic name': InvalidTopicNameException, 'service name': InvalidServiceNameException,
          'action name': InvalidServiceNameException}


def _invalid(kind: str, text: str) -> InvalidNameError:
    """The error for a bad name of `kind`: rclpy's class for that kind of name."""
    return _KINDS.get(kind, InvalidNameError)(text)


_NODE_NAME = re.compile(r'^[A-Za-z_][A-Za-z0-9_]*$')
_TOKEN = re.compile(r'^[A-Za-z_][A-Za-z0-9_]*$')
# Characters that explain a rejection best when named (Zenoh wildcards and key separators).
_ZENOH_SPECIAL = set('*$#?')


def _explain_bad_char(kind: str, name: str, allowed: str = '_/') -> str:
    """rcl's reason ("must not contain characters other than ..."), naming the character found."""
    others = "alphanumerics and '_'" if allowed == '_' else "alphanumerics, '_', '~', '{', '}' and '/'"
    for ch in name:
        if ch in _ZENOH_SPECIAL:
            return (f"invalid {kind} '{name}': must not contain characters other than {others}: "
                    f"'{ch}' is a Zenoh wildcard")
    for ch in name:
        if not (ch.isalnum() and ch.isascii()) and ch not in allowed:
            return f"invalid {kind} '{name}': must not contain characters other than {others}: '{ch}'"
    return ''


def validate_node_name(name: str) -> str:
    """Return `name` if it is a valid node name (no slashes, no leading digit)."""
    if not isinstance(name, str) or not name:
        raise _invalid('node name', 'node name must not be empty (a non-empty string)')
    if not _NODE_NAME.match(name):
        reason = _explain_bad_char('node name', name, allowed='_')
        if not reason:
            reason = f"invalid node name '{name}': must not start with a number: start with a letter or '_'"
        raise _invalid('node name', reason)
    return name


def _validate_tokens(kind: str, name: str, body: str) -> None:
    for token in body.split('/'):
        if not token:
            raise _invalid(kind, f"invalid {kind} '{name}': must not contain repeated '/' ('//') or end with '/' "
                                 "(an empty token)")
        if not _TOKEN.match(token):
            reason = _explain_bad_char(kind, name)
            if not reason:
                reason = f"invalid {kind} '{name}': token '{token}' must not start with a number (a digit)"
            raise _invalid(kind, reason)


def validate_namespace(namespace: str) -> str:
    """Return `namespace` if it is absolute and well formed ('/' is the root namespace)."""
    if not isinstance(namespace, str) or not namespace:
        raise _invalid('namespace', 'namespace must not be empty')
    if not namespace.startswith('/'):
        raise _invalid('namespace', f"invalid namespace '{namespace}': must be absolute (start with '/')")
    if namespace != '/':
        _validate_tokens('namespace', namespace, namespace[1:])
    return namespace


def validate_full_name(name: str, kind: str = 'topic name') -> str:
    """Return `name` if it is a valid fully qualified (absolute, expanded) name."""
    if not isinstance(name, str) or not name.startswith('/') or name == '/':
        raise _invalid(kind, f"invalid {kind} '{name}': must be absolute and not '/'")
    _validate_tokens(kind, name, name[1:])
    return name


def normalize_namespace(namespace: str | None) -> str:
    """Make a user-given namespace absolute: None and '' mean '/', 'robot' means '/robot'."""
    if not namespace:
        return '/'
    if not namespace.startswith('/'):
        namespace = '/' + namespace
    if len(namespace) > 1 and namespace.endswith('/'):
        namespace = namespace.rstrip('/') or '/'
    return validate_namespace(namespace)


def fully_qualified_node_name(namespace: str, node_name: str) -> str:
    return f'/{node_name}' if namespace == '/' else f'{namespace}/{node_name}'


def expand_topic_name(name: str, node_name: str, namespace: str, kind: str = 'topic name') -> str:
    """Expand a relative, private (`~`) or absolute name to its fully qualified form.

    Follows rcl_expand_topic_name: `~` is the node's fully qualified name, `{node}` and `{ns}`
    substitutions are supported, relative names go under the namespace.
    """
    if not isinstance(name, str):
        raise TypeError(f'{kind} must be a str, got {type(name).__name__}')   # as rclpy's C binding
    if not name:
        raise _invalid(kind, f'{kind} must not be empty (a non-empty string)')
    original = name
    if '{' in name or '}' in name:
        ns_sub = '' if namespace == '/' else namespace
        name = name.replace('{node}', node_name).replace('{ns}', ns_sub).replace('{namespace}', ns_sub)
        if '{' in name or '}' in name:
            raise _invalid(kind, f"invalid {kind} '{original}': unknown substitution")
    fq_node = fully_qualified_node_name(namespace, node_name)
    if name == '~':
        name = fq_node
    elif name.startswith('~/'):
        name = fq_node + name[1:]
    elif name.startswith('~'):
        raise _invalid(kind, f"invalid {kind} '{original}': '~' must be followed by '/'")
    elif not name.startswith('/'):
        name = ('' if namespace == '/' else namespace) + '/' + name
    try:
        return validate_full_name(name, kind)
    except InvalidNameError as exc:
        if name != original:
            raise type(exc)(f"{exc} (expanded from '{original}')") from None
        raise


@dataclass
class Remappings:
    """The `--ros-args -r` rules that apply to one node.

    `rules` maps an expanded source name to an expanded target; `node_name` / `namespace` are
    the `__node:=` / `__ns:=` overrides. Rules given as `node:from:=to` apply only to that node.
    """

    rules: list[tuple[str | None, str, str]] = field(default_factory=list)  # (node, from, to)
    node_name: str | None = None
    namespace: str | None = None

    def add(self, rule: str) -> None:
        """Add one `[node:]from:=to` rule, as given after `-r`."""
        if ':=' not in rule:
            raise InvalidNameError(f"invalid remapping rule '{rule}': expected 'from:=to'")
        lhs, rhs = rule.split(':=', 1)
        node = None
        if ':' in lhs:
            node, lhs = lhs.split(':', 1)
        if not lhs or not rhs:
            raise InvalidNameError(f"invalid remapping rule '{rule}': empty side")
        if lhs in ('__node', '__name'):
            validate_node_name(rhs)
            if node is None:
                self.node_name = rhs
            else:
                self.rules.append((node, '__node', rhs))
            return
        if lhs == '__ns':
            ns = normalize_namespace(rhs)
            if node is None:
                self.namespace = ns
            else:
                self.rules.append((node, '__ns', ns))
            return
        self.rules.append((node, lhs, rhs))

    def node_overrides(self, node_name: str) -> tuple[str | None, str | None]:
        """(name, namespace) overrides for the node originally called `node_name`."""
        name, ns = self.node_name, self.namespace
        for node, lhs, rhs in self.rules:
            if node == node_name:
                if lhs == '__node':
                    name = rhs
                elif lhs == '__ns':
                    ns = rhs
        return name, ns

    def apply(self, fq_name: str, node_name: str, namespace: str, original_node_name: str | None = None) -> str:
        """Return the remapped fully qualified name (or `fq_name` when no rule matches).

        The first matching rule wins, as in rcl. Both sides of a rule are expanded against the
        node's final name and namespace before comparing.
        """
        for node, lhs, rhs in self.rules:
            if lhs in ('__node', '__ns'):
                continue
            if node is not None and node not in (node_name, original_node_name):
                continue
            if expand_topic_name(lhs, node_name, namespace) == fq_name:
                return expand_topic_name(rhs, node_name, namespace)
        return fq_name
