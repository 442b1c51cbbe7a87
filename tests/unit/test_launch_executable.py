"""zros.launch.descriptions.Executable and ExecuteLocal: what a process action resolves to
(command, prefix, name, working directory, whole environment) and launch's views of it."""
from __future__ import annotations

import sys

import pytest

from zros.launch import LaunchContext
from zros.launch.actions import ExecuteLocal, ExecuteProcess, Shutdown, TimerAction
from zros.launch.descriptions import Executable
from zros.launch.errors import LaunchFileError
from zros.launch.frontend import Parser
from zros.launch.plan import ProcessSpec, TimerEffect
from zros.launch.substitutions import EnvironmentVariable, LaunchConfiguration


def context_with(**configurations: str) -> LaunchContext:
    context = LaunchContext(environment={'HOME': '/home/me', 'KEEP': 'yes'})
    context.configurations.update(configurations)
    return context


def test_prepare_resolves_each_item_as_one_argument_and_the_whole_environment():
    exe = Executable(cmd=['ls', 'a b'], name=EnvironmentVariable('HOME'), cwd='/tmp',
                     additional_env={'EXTRA': '1'}, arguments=['-l'])
    exe.prepare(context_with(), None)
    assert exe.final_cmd == ['ls', 'a b', '-l']
    assert (exe.final_name, exe.final_cwd) == ('/home/me', '/tmp')
    assert exe.final_env == {'HOME': '/home/me', 'KEEP': 'yes', 'EXTRA': '1'}


def test_env_replaces_the_environment_and_additional_env_adds_to_it():
    exe = Executable(cmd=['true'], env={'ONLY': 'this'}, additional_env={'AND': 'that'})
    exe.prepare(context_with(), None)
    assert exe.final_env == {'ONLY': 'this', 'AND': 'that'}


@pytest.mark.parametrize('prefix_filter, prefixed', [('', True), ('py.*', True), ('gdb', False)])
def test_launch_prefix_applies_to_programs_the_filter_matches(prefix_filter, prefixed):
    exe = Executable(cmd=['python3', '-V'])
    exe.prepare(context_with(**{'launch-prefix': 'time -v', 'launch-prefix-filter': prefix_filter}))
    assert exe.final_cmd == (['time', '-v'] if prefixed else []) + ['python3', '-V']


def test_an_explicit_prefix_ignores_the_filter():
    exe = Executable(cmd=['python3'], prefix='echo')
    exe.prepare(context_with(**{'launch-prefix': 'time', 'launch-prefix-filter': 'nothing'}))
    assert exe.final_cmd == ['echo', 'python3']


def test_execute_process_is_execute_local_over_an_executable():
    action = ExecuteProcess(cmd=[sys.executable, '-c', 'pass'], name='worker', additional_env={'A': '1'})
    assert isinstance(action, ExecuteLocal) and isinstance(action.process_description, Executable)
    context = context_with()
    action.execute(context)
    [spec] = [effect for effect in context.effects if isinstance(effect, ProcessSpec)]
    assert spec.label == 'worker' and spec.cmd_head == (sys.executable, '-c', 'pass')
    assert action.process_details['cmd'] == [sys.executable, '-c', 'pass']
    assert action.process_details['env']['A'] == '1' and action.process_details['env']['KEEP'] == 'yes'


def test_execute_local_takes_launchs_output_dictionary():
    def mode(output):
        return ExecuteLocal(process_description=Executable(cmd=['true']), output=output).output.perform(None)
    assert mode({'stdout': 'screen', 'stderr': 'screen'}) == 'screen'
    assert mode({'stderr': {'screen', 'log'}}) == 'log'
    assert mode({'both': 'own_log'}) == 'own_log'
    with pytest.raises(LaunchFileError):
        mode({'stdin': 'screen'})


def test_on_exit_actions_are_the_sub_entities_and_a_function_has_none():
    stop = Shutdown()
    assert ExecuteProcess(cmd=['true'], on_exit=[stop]).get_sub_entities() == [stop]
    assert ExecuteProcess(cmd=['true'], on_exit=lambda event, context: None).get_sub_entities() == []


def test_parsed_executable_reads_as_launch_keeps_it():
    root, parser = Parser.load(__import__('io').StringIO(
        'launch:\n- executable: {cmd: ls -l $(env HOME), shell: true, sigterm_timeout: 7.0}\n'))
    action = parser.parse_description(root).entities[0]
    assert [argument[0].perform(None) for argument in action.cmd[:2]] == ['ls', '-l']
    assert isinstance(action.cmd[2][0], EnvironmentVariable)
    assert action.shell is True and action.emulate_tty is False
    assert action.sigterm_timeout[0].perform(None) == '7.0'


def test_timer_period_is_a_float_or_the_substitutions_that_give_it():
    assert TimerAction(period=2, actions=[]).period == 2.0
    [substitution] = TimerAction(period=LaunchConfiguration('t'), actions=[]).period
    assert isinstance(substitution, LaunchConfiguration)


def test_a_timer_kept_over_shutdown_says_so_in_its_effect():
    context = context_with()
    from zros.launch.description import walk
    walk([TimerAction(period=1.0, actions=[Shutdown()], cancel_on_shutdown=False)], context)
    [timer] = context.effects
    assert isinstance(timer, TimerEffect) and timer.cancel_on_shutdown is False


def test_shutdown_on_a_bare_context_is_queued_as_the_event_and_in_a_launch_is_a_plan_point():
    from zros.launch.description import walk
    from zros.launch.events import Shutdown as ShutdownEvent
    from zros.launch.plan import ShutdownEffect
    bare = LaunchContext()
    assert Shutdown(reason='by hand').visit(bare) is None
    event = bare._event_queue.get_nowait()
    assert isinstance(event, ShutdownEvent) and event.reason == 'by hand'
    launching = LaunchContext()
    level = launching.begin_capture()
    walk([Shutdown(reason='planned')], launching)
    [effect] = launching.end_capture(level)
    assert isinstance(effect, ShutdownEffect) and effect.reason == 'planned'
    assert launching._event_queue.empty()


def test_ending_a_capture_by_level_closes_captures_left_open_inside_it():
    context = LaunchContext()
    level = context.begin_capture()
    context.emit('mine')
    context.begin_capture()   # an action executed by hand, its EndCapture never visited
    context.emit('lost')
    assert context.end_capture(level) == ['mine'] and not context.collecting_effects
