"""`opennav_docking docking_server`: the executable a launch file's
`ComposableNode(package='opennav_docking', plugin='opennav_docking::DockingServer')` resolves to
(zros runs composable nodes as processes); the same node as `opennav_docking opennav_docking`."""
from nodes.opennav_docking.opennav_docking import main

__all__ = ['main']
