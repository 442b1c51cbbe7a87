"""rclpy.validate_full_topic_name: raise for a bad fully qualified topic or service name."""
from zros.names import validate_full_name


def validate_full_topic_name(name: str, *, is_service: bool = False) -> bool:
    """True for a valid absolute name; raises InvalidTopicNameException (InvalidServiceNameException
    with `is_service`) otherwise."""
    validate_full_name(name, 'service name' if is_service else 'topic name')
    return True
