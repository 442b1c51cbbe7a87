"""A type's hash as ROS 2 states it (rclpy.type_hash): REP-2011's RIHS version and digest.

rclpy's endpoint infos carry one. zros's graph announces its own, shorter hash instead (16 hex
digits of what goes on the wire, zros.message.type_hash), which is no RIHS hash: an endpoint
info built from it holds TypeHash(), printed INVALID, and `zros topic info -v` computes the
RIHS01 text itself (docs/porting.md).
"""
from __future__ import annotations

__all__ = ['TypeHash']

_DIGEST_SIZE = 32  # [bytes] a SHA-256 digest


class _Typed:
    """A slot-backed attribute that takes values of one type only (rclpy asserts them)."""

    def __init__(self, kind: type, doc: str) -> None:
        self._kind = kind
        self.__doc__ = doc

    def __set_name__(self, owner: type, name: str) -> None:
        self._name, self._slot = name, '_' + name

    def __get__(self, obj: object, owner: type | None = None) -> object:
        return self if obj is None else getattr(obj, self._slot)

    def __set__(self, obj: object, value: object) -> None:
        if not isinstance(value, self._kind):
            raise TypeError(f'a type hash {self._name} must be {self._kind.__name__}, got {type(value).__name__}')
        setattr(obj, self._slot, value)


class TypeHash:
    """A version and a 32-byte digest; version -1 (the default) stands for no hash.

    :param version: The RIHS version, 1 for the hashes Jazzy computes.
    :param value: The digest.
    """

    __slots__ = ('_version', '_value')   # slots, as tools written for rclpy's class expect

    def __init__(self, version: int = -1, value: bytes = bytes(_DIGEST_SIZE)) -> None:
        self.version = version
        self.value = value

    @classmethod
    def from_string(cls, text: str) -> 'TypeHash':
        """Read `RIHS01_<hex>`; any other text (no hash, a malformed one) gives TypeHash()."""
        prefix, _, digest = text.partition('_')
        try:
            if not prefix.startswith('RIHS'):
                raise ValueError(prefix)
            return cls(int(prefix[4:]), bytes.fromhex(digest))
        except ValueError:
            return cls()

    version = _Typed(int, 'The RIHS version (-1: no hash).')
    value = _Typed(bytes, 'The digest.')

    def __eq__(self, other: object) -> bool:
        return isinstance(other, TypeHash) and (self._version, self._value) == (other._version, other._value)

    def __hash__(self) -> int:
        return hash((self._version, self._value))

    def __str__(self) -> str:
        """`RIHS01_<hex>`, or `INVALID` for no hash (a version below 1 or a digest of another size)."""
        if self._version <= 0 or len(self._value) != _DIGEST_SIZE:
            return 'INVALID'
        return f'RIHS{self._version:02}_{self._value.hex()}'

    def __repr__(self) -> str:
        return f'TypeHash({self})'
