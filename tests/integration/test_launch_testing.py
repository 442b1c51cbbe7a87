"""launch_testing files run unchanged, by pytest (as `colcon test` runs them) and by `zros test`
(ROS's `launch_test`): seed 003's integration test, a failing wait, post-shutdown exit codes,
launch arguments, the old-style ready_fn, and files that cannot run."""
from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import assert_clean_failure, kill_group, run_cli
from zros.launch_testing.tools import expect_output, find_text

# seed 003 ("Integration Testing"), as printed; only its `my_package` is zros's demo_nodes (whose
# listener says "I heard: [Hello World: 1]"), with the add_two_ints_server answering on 'add'.
SEED_003 = '''import launch_testing
import unittest
from launch import LaunchDescription
from launch_ros.actions import Node

def generate_test_description():
    # Launch nodes for testing
    return LaunchDescription([
        Node(package='demo_nodes', executable='talker'),
        Node(package='demo_nodes', executable='listener'),
        Node(package='demo_nodes', executable='add_two_ints_server', remappings=[('add_two_ints', 'add')]),
        launch_testing.actions.ReadyToTest()
    ])

class TestCommunication(unittest.TestCase):
    def test_topic_communication(self, proc_output):
        # Wait for expected output
        proc_output.assertWaitFor('I heard: [Hello', timeout=5)

    def test_service_response(self):
        import rclpy
        from example_interfaces.srv import AddTwoInts

        node = rclpy.create_node('test_client')
        client = node.create_client(AddTwoInts, 'add')

        request = AddTwoInts.Request(a=2, b=3)
        future = client.call_async(request)
        rclpy.spin_until_future_complete(node, future)

        assert future.result().sum == 5
'''

NEVER_PRINTED = '''import unittest
import launch_testing
from launch import LaunchDescription
from launch_ros.actions import Node

def generate_test_description():
    return LaunchDescription([Node(package='demo_nodes', executable='talker'),
                              launch_testing.actions.ReadyToTest()])

class TestTalker(unittest.TestCase):
    def test_says_goodbye(self, proc_output):
        proc_output.assertWaitFor('Goodbye', process='talker', timeout=1)
'''

# A worker that prints and exits; the dict form gives the tests its action by name.
EXIT_CODES = '''import sys
import unittest
import launch_testing
import launch_testing.asserts
import launch_testing.markers
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, ExecuteProcess
from launch.substitutions import LaunchConfiguration

@launch_testing.markers.keep_alive
def generate_test_description():
    worker = ExecuteProcess(cmd=[sys.executable, '-c', 'import sys; print(sys.argv[1]); print("done")',
                                 LaunchConfiguration('greeting')], name='worker', output='screen')
    return LaunchDescription([DeclareLaunchArgument('greeting', default_value='hi'), worker,
                              launch_testing.actions.ReadyToTest()]), {'worker': worker}

class TestWorker(unittest.TestCase):
    def test_worker_finishes(self, proc_info, worker, test_args):
        proc_info.assertWaitForShutdown(process=worker, timeout=10)
        self.assertEqual(test_args.get('greeting', 'hi'), self.expected)

    expected = 'hi'

@launch_testing.post_shutdown_test()
class TestAfterShutdown(unittest.TestCase):
    def test_exit_codes(self, proc_info):
        launch_testing.asserts.assertExitCodes(proc_info, [launch_testing.asserts.EXIT_OK])

    def test_output_in_order(self, proc_output, worker):
        with launch_testing.asserts.assertSequentialStdout(proc_output, worker) as lines:
            lines.assertInStdout(self.expected)
            lines.assertInStdout('done')

    expected = 'hi'
'''

# Old style: generate_test_description(ready_fn), called from an OpaqueFunction; exits 3.
EXIT_THREE = '''import sys
import unittest
import launch_testing
from launch import LaunchDescription
from launch.actions import ExecuteProcess, OpaqueFunction

def generate_test_description(ready_fn):
    return LaunchDescription([
        ExecuteProcess(cmd=[sys.executable, '-c', 'import sys; sys.exit(3)'], name='crasher'),
        launch_testing.util.KeepAliveProc(),
        OpaqueFunction(function=lambda context: ready_fn()),
    ])

class TestCrasher(unittest.TestCase):
    def test_crasher_ends(self, proc_info):
        proc_info.assertWaitForShutdown('crasher', timeout=10)

@launch_testing.post_shutdown_test()
class TestExitCodes(unittest.TestCase):
    def test_exit_codes(self, proc_info):
        launch_testing.asserts.assertExitCodes(proc_info, process='crasher')
'''

NO_READY = '''import unittest
from launch import LaunchDescription
from launch_ros.actions import Node

def generate_test_description():
    return LaunchDescription([Node(package='demo_nodes', executable='talker')])

class TestNothing(unittest.TestCase):
    def test_nothing(self):
        pass
'''


def write(directory: Path, name: str, text: str) -> Path:
    path = directory / name
    path.write_text(text)
    return path


def run_pytest(path: Path, *args: str, timeout: float = 90.0) -> subprocess.CompletedProcess:
    """pytest on one file, in its own directory (zros's plugin comes from the entry point)."""
    argv = [sys.executable, '-m', 'pytest', '-q', '-p', 'no:cacheprovider', str(path), *args]
    popen = subprocess.Popen(argv, cwd=path.parent, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                             stdin=subprocess.DEVNULL, text=True, start_new_session=True)
    try:
        out, _ = popen.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        kill_group(popen)
        pytest.fail(f'pytest {path.name} did not finish within {timeout} s: {popen.communicate()[0]}')
    return subprocess.CompletedProcess(argv, popen.returncode, out, '')


def zros_test(path: Path, *args: str, timeout: float = 90.0):
    return run_cli('test', path, '--log-dir', path.parent / 'log', *args, timeout=timeout)


# -- fast: matching --------------------------------------------------------------------------
def test_expected_output_is_text_a_pattern_or_a_sequence():
    assert find_text('World', 'Hello World') == (6, 11)
    assert find_text(re.compile(r'W\w+'), 'Hello World') == (6, 11)
    assert find_text(['one', 'three'], 'one two three') == (0, 13)
    assert find_text(['three', 'one'], 'one two three') is None
    assert expect_output(lines=['a', 'b', 'c'], expected_lines=['a', 'c'])
    assert not expect_output(lines=['a', 'b'], expected_lines=['b', 'a'])


# -- the seed --------------------------------------------------------------------------------
def test_seed_003_integration_test_passes_under_pytest(tmp_path, domain):
    result = run_pytest(write(tmp_path, 'test_communication.py', SEED_003))
    assert result.returncode == 0, result.stdout
    assert '1 passed' in result.stdout, result.stdout


def test_seed_003_integration_test_passes_under_zros_test(tmp_path, domain):
    result = zros_test(write(tmp_path, 'test_communication.py', SEED_003))
    assert result.returncode == 0, result
    assert 'test_service_response' in result.stderr and 'test_topic_communication' in result.stderr, result
    assert 'Ran 2 tests' in result.stderr and '\nOK' in result.stderr, result


# -- failures are failures, with the reason -------------------------------------------------
def test_a_wait_for_output_that_never_comes_fails_in_time(tmp_path, domain):
    path = write(tmp_path, 'test_goodbye.py', NEVER_PRINTED)
    result = run_pytest(path)
    assert result.returncode == 1, result.stdout
    assert "timed out after 1 s waiting for 'Goodbye' on stderr of any of talker-1" in result.stdout, result.stdout
    assert 'FAIL: test_goodbye.TestTalker.test_says_goodbye' in result.stdout, result.stdout
    cli = zros_test(path)
    assert cli.returncode == 1, cli
    assert 'zros test: 1 test(s) failed: test_goodbye.TestTalker.test_says_goodbye' in cli.stderr, cli


def test_post_shutdown_tests_see_exit_codes_and_output(tmp_path, domain):
    path = write(tmp_path, 'test_worker.py', EXIT_CODES)
    result = run_pytest(path)
    assert result.returncode == 0, result.stdout
    cli = zros_test(write(tmp_path, 'test_worker_args.py', EXIT_CODES.replace("expected = 'hi'", "expected = 'hey'")),
                    'greeting:=hey')
    assert cli.returncode == 0, cli
    assert 'test_exit_codes' in cli.stderr and 'test_output_in_order' in cli.stderr, cli
    assert '[worker-1] hey' in cli.stdout, cli


def test_a_bad_exit_code_fails_the_post_shutdown_test(tmp_path, domain):
    result = zros_test(write(tmp_path, 'test_crasher.py', EXIT_THREE))
    assert result.returncode == 1, result
    assert 'Proc crasher-1 exited with code 3 (allowed: 0)' in result.stderr, result
    assert 'zros test: 1 test(s) failed: test_crasher.TestExitCodes.test_exit_codes' in result.stderr, result


# -- files that cannot run ------------------------------------------------------------------
def test_a_file_without_generate_test_description_is_one_line(tmp_path):
    path = write(tmp_path, 'test_plain.py', 'import launch_testing\n')
    assert_clean_failure(zros_test(path), 'test_plain.py: no generate_test_description() function')


def test_a_description_without_ready_to_test_is_one_line(tmp_path):
    path = write(tmp_path, 'test_no_ready.py', NO_READY)
    assert_clean_failure(zros_test(path), 'test_no_ready.py: generate_test_description() returned a '
                                          'LaunchDescription without launch_testing.actions.ReadyToTest()')
    result = run_pytest(path)
    assert result.returncode == 1, result.stdout
    assert 'without launch_testing.actions.ReadyToTest()' in result.stdout and 'Traceback' not in result.stdout, \
        result.stdout
