"""zros's nav2_common: the launch helpers Nav2's launch files import (`from nav2_common.launch
import RewrittenYaml`), so nav2_bringup's launch files run as Nav2 ships them."""
from zros.nav2_common import launch

__all__ = ['launch']
