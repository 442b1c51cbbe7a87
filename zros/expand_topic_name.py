"""rclpy.expand_topic_name: the fully qualified form of a topic name for a node."""
from zros.names import expand_topic_name as _expand, validate_namespace, validate_node_name


def expand_topic_name(topic_name: str, node_name: str, node_namespace: str) -> str:
    """`topic_name` expanded for `node_name` in `node_namespace` (`~`, `{node}`, relative names).

    :raises ValueError: (an InvalidNameError) naming the node name, namespace or topic name at fault.
    """
    validate_node_name(node_name)
    validate_namespace(node_namespace)
    return _expand(topic_name, node_name, node_namespace)
