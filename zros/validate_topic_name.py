"""rclpy.validate_topic_name: raise for a bad topic or service name, before expansion.

A relative, private (`~/x`) or substituted (`{node}/x`) name is checked as it would expand
under a placeholder node, so its own tokens are what is judged."""
from zros.names import expand_topic_name


def validate_topic_name(name: str, *, is_service: bool = False) -> bool:
    """True for a valid topic name; raises InvalidTopicNameException (InvalidServiceNameException
    with `is_service`) otherwise."""
    expand_topic_name(name, 'node', '/', 'service name' if is_service else 'topic name')
    return True
