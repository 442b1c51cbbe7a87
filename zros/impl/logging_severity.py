"""`rclpy.impl.logging_severity`'s path for the severity enum; the enum itself is zros.logging's."""
from zros.logging import LoggingSeverity

__all__ = ['LoggingSeverity']
