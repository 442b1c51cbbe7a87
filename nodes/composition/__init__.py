"""`composition`: ROS 2's composition demo package, whose components launch files load by plugin
name (`ComposableNode(package='composition', plugin='composition::Talker')`).

zros runs a composable node as a process of its own (zros.launch.actions.composable): the
plugin `composition::Talker` is the executable `talker` here, and so on. The components behave
as the demo's: Talker publishes 'Hello World: N' on chatter once a second, Listener echoes what
arrives on chatter; they are demo_nodes' talker and listener, whose node names they share.
"""
