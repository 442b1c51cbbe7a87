"""rclpy.validate_namespace: raise InvalidNamespaceException for a bad namespace."""
from zros.names import validate_namespace as _validate


def validate_namespace(namespace: str) -> bool:
    """True for a valid (absolute) namespace; raises InvalidNamespaceException otherwise."""
    _validate(namespace)
    return True
