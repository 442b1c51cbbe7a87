"""launch_testing on zros: ROS 2 integration tests run unchanged (`import launch_testing`).

A launch test module defines `generate_test_description()`, returning a LaunchDescription
with `launch_testing.actions.ReadyToTest()` (or `(description, {name: action})`), plus
unittest.TestCase classes: those without a mark run while the launch is up, with
`proc_output`, `proc_info`, `launch_service`, `test_args` and the returned names as
arguments; those marked `@launch_testing.post_shutdown_test()` run after it ended, typically
`launch_testing.asserts.assertExitCodes(proc_info)`.

Run one with pytest (zros's pytest plugin collects every test module that defines
generate_test_description, as `colcon test` runs them) or with `zros test FILE [name:=value]`
(ROS's `launch_test`). How a run goes: zros.launch_testing.runner.
"""
from __future__ import annotations

from zros.launch_testing import actions, asserts, markers, tools, util  # noqa: F401 - launch_testing.actions...
from zros.launch_testing.decorator import post_shutdown_test, ready_to_test_action_timeout
from zros.launch_testing.handlers import ActiveIoHandler, ActiveProcInfoHandler, IoHandler, ProcInfoHandler
from zros.launch.files import module_getattr

__all__ = ['actions', 'asserts', 'markers', 'tools', 'util', 'post_shutdown_test', 'ready_to_test_action_timeout',
           'IoHandler', 'ActiveIoHandler', 'ProcInfoHandler', 'ActiveProcInfoHandler']

__getattr__ = module_getattr(__name__)   # parametrize, ReadyAggregator: one line saying what there is
