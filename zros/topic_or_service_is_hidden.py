"""rclpy.topic_or_service_is_hidden: whether a name is hidden from introspection (a token that
starts with '_', as `ros2 topic list` hides without --include-hidden-topics)."""

HIDDEN_TOPIC_PREFIX = '_'


def topic_or_service_is_hidden(name: str) -> bool:
    """True when any '/'-separated token of `name` starts with '_'."""
    return any(token.startswith(HIDDEN_TOPIC_PREFIX) for token in name.split('/'))
