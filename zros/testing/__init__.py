"""Testing zros nodes with pytest: isolated domains, nodes in-process or as processes, waits.

launch_testing's job without its ceremony. Installed with zros, the pytest plugin
(zros.testing.plugin, loaded automatically) gives every test that asks for them:

- `zros_domain`: a private domain id (ZROS_DOMAIN_ID for the test and every process it
  starts), so tests running at the same time on one machine never see each other;
- `zros_context`: zros initialized in that domain for this process (`zros.init()`), shut down
  after the test, so node classes can be constructed as in a program;
- `zros_node`: `zros_node('probe')` -> a Node in that context, destroyed after the test;
- `zros_processes`: `zros_processes.run('my_pkg', 'my_node', '--ros-args', ...)`,
  `.launch('file.launch.py', 'name:=value')` or `.command(*argv)`: real processes, whose output
  is kept for `wait_for_output`, stopped (and killed if they must be) after the test.

The helpers below wait on a node with a timeout and fail with a clear message:
`wait_for_message(node, String, '/chatter')`, `call_service(node, AddTwoInts, '/add',
request)`, `wait_for_node(node, '/talker')`, `wait_for_topic(node, '/chatter')`,
`spin_until(node, predicate)`, `wait_until(predicate)`. They spin the node themselves, so the
node must not be spinning in another executor at the same time.
"""
from __future__ import annotations

from zros.testing.domains import DomainLock, isolated_environment
from zros.testing.processes import Child, ProcessGroup
from zros.testing.waits import (WaitTimeout, call_service, spin_until, wait_for_message, wait_for_node,
                                wait_for_topic, wait_until)

__all__ = ['DomainLock', 'isolated_environment', 'Child', 'ProcessGroup', 'WaitTimeout', 'wait_until',
           'spin_until', 'wait_for_message', 'wait_for_node', 'wait_for_topic', 'call_service']
