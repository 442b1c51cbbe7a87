"""rclpy.validate_node_name: raise InvalidNodeNameException for a bad node name."""
from zros.names import validate_node_name as _validate


def validate_node_name(node_name: str) -> bool:
    """True for a valid node name; raises InvalidNodeNameException (with rcl's reason) otherwise."""
    _validate(node_name)
    return True
