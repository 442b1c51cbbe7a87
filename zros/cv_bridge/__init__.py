"""`zros.cv_bridge`: ROS's cv_bridge (CvBridge, CvBridgeError) on numpy, OpenCV optional."""
from zros.cv_bridge.core import CvBridge, CvBridgeError

__all__ = ['CvBridge', 'CvBridgeError']
