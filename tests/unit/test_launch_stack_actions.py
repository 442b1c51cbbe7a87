"""The stack actions and the context they work on, visited by hand as launch's own tests do:
push/pop of configurations and environment, resets, unset, the group's expansion into them,
DeclareLaunchArgument's launch-shaped attributes, context locals, and the per-action modules."""
from __future__ import annotations

import importlib

import pytest

from zros.launch import LaunchContext, LaunchDescription, LaunchDescriptionEntity, LaunchError
from zros.launch.actions import (AppendEnvironmentVariable, DeclareLaunchArgument, GroupAction, LogInfo,
                                 OpaqueFunction,
                                 PopEnvironment, PopLaunchConfigurations, PushEnvironment, PushLaunchConfigurations,
                                 ResetEnvironment, ResetLaunchConfigurations, SetEnvironmentVariable,
                                 SetLaunchConfiguration, UnsetLaunchConfiguration)
from zros.launch.substitutions import LaunchConfiguration


def fresh() -> LaunchContext:
    return LaunchContext(environment={'HOME': '/home/me'})


def visit_all(actions, context: LaunchContext) -> None:
    for action in actions:
        visit_all(action.visit(context) or [], context)


def test_configurations_come_back_after_a_pop_with_the_ros_scope():
    context = fresh()
    context.launch_configurations['kept'] = 'before'
    PushLaunchConfigurations().visit(context)
    context.launch_configurations['kept'] = 'inside'
    context.launch_configurations['added'] = 'x'
    context.ros.namespace = '/robot'
    PopLaunchConfigurations().visit(context)
    assert dict(context.launch_configurations) == {'kept': 'before'}
    assert context.ros.namespace == ''


def test_environment_pops_and_resets_to_where_the_launch_started():
    context = fresh()
    context.environment['EXTRA'] = '1'
    PushEnvironment().visit(context)
    del context.environment['HOME']
    ResetEnvironment().visit(context)
    assert context.environment == {'HOME': '/home/me'}   # the start, not the pushed copy
    PopEnvironment().visit(context)
    assert context.environment == {'HOME': '/home/me', 'EXTRA': '1'}


def test_a_pop_without_a_push_is_an_error_that_is_also_a_runtime_error():
    with pytest.raises(LaunchError, match='without a PushEnvironment'):
        PopEnvironment().visit(fresh())
    with pytest.raises(RuntimeError, match='without a PushLaunchConfigurations'):
        PopLaunchConfigurations().visit(fresh())


def test_unset_forgets_a_configuration_and_ignores_a_missing_one():
    context = fresh()
    SetLaunchConfiguration('robot', 'r1').visit(context)
    UnsetLaunchConfiguration(['rob', 'ot']).visit(context)
    UnsetLaunchConfiguration('never_set').visit(context)
    assert 'robot' not in context.launch_configurations


def test_reset_keeps_only_the_values_it_is_given_evaluated_before_clearing():
    context = fresh()
    context.launch_configurations.update({'a': 'A', 'b': 'B'})
    ResetLaunchConfigurations({'copy_of_a': LaunchConfiguration('a')}).visit(context)
    assert dict(context.launch_configurations) == {'copy_of_a': 'A'}


def test_a_group_returns_its_children_between_the_stack_actions():
    context = fresh()
    inner = LogInfo(msg='x')
    kinds = [type(a) for a in GroupAction([inner], launch_configurations={'k': 'v'}).visit(context)]
    assert kinds == [PushLaunchConfigurations, PushEnvironment, SetLaunchConfiguration, LogInfo,
                     PopEnvironment, PopLaunchConfigurations]
    kinds = [type(a) for a in GroupAction([inner], forwarding=False).visit(context)]
    assert kinds == [PushLaunchConfigurations, PushEnvironment, ResetEnvironment, ResetLaunchConfigurations,
                     LogInfo, PopEnvironment, PopLaunchConfigurations]
    assert [type(a) for a in GroupAction([inner], scoped=False).visit(context)] == [LogInfo]


def test_a_non_forwarding_group_starts_from_the_launch_environment():
    context = fresh()
    inside = {}

    def record(context):
        inside.update(environment=dict(context.environment), configurations=dict(context.configurations))
    visit_all([SetEnvironmentVariable('OUTER', '1'), SetLaunchConfiguration('outer', 'o'),
               GroupAction([AppendEnvironmentVariable('PATHS', 'a', prepend='yes'), OpaqueFunction(function=record)],
                           forwarding=False, launch_configurations={'keep': LaunchConfiguration('outer')})],
              context)
    assert inside == {'environment': {'HOME': '/home/me', 'PATHS': 'a'}, 'configurations': {'keep': 'o'}}
    assert context.environment == {'HOME': '/home/me', 'OUTER': '1'}


def test_declare_launch_argument_reads_like_launchs():
    argument = DeclareLaunchArgument('mode', default_value='fast', choices=['fast', 'slow'])
    assert argument.choices == ['fast', 'slow']
    assert [s.perform(fresh()) for s in argument.default_value] == ['fast']
    assert argument.description == "One of: ['fast', 'slow']"
    assert DeclareLaunchArgument('x').description == 'no description given'
    assert DeclareLaunchArgument('x').default_value is None and DeclareLaunchArgument('x').choices is None
    with pytest.raises(RuntimeError, match='not in provided choices'):
        DeclareLaunchArgument('mode', default_value='medium', choices=['fast', 'slow'])
    with pytest.raises(RuntimeError, match="Required launch argument 'x'"):
        DeclareLaunchArgument('x').visit(fresh())
    assert argument.visit(fresh()) is None
    assert 'DeclareLaunchArgument' in argument.describe()
    assert argument.describe_conditional_sub_entities() == []


def test_context_locals_are_read_only_attributes_with_globals_underneath():
    context = LaunchContext(argv=['a:=1'], noninteractive=True)
    assert context.argv == ['a:=1'] and context.noninteractive and not context.is_shutdown
    context.extend_globals({'shared': 1, 'event': 'global'})
    context.extend_locals({'event': 'local'})
    assert context.get_locals_as_dict() == {'shared': 1, 'event': 'local'}
    assert context.locals.event == 'local'
    with pytest.raises(AttributeError, match='has no'):
        context.locals.missing
    with pytest.raises(AttributeError, match='read-only'):
        context.locals.event = 'x'
    context._push_locals()
    context.extend_locals({'event': 'inner', 'only_inner': 2})
    assert context.locals.event == 'inner'
    context._pop_locals()
    assert context.get_locals_as_dict() == {'shared': 1, 'event': 'local'}
    with pytest.raises(RuntimeError):
        context._pop_locals()


def test_actions_and_descriptions_are_launch_description_entities():
    assert isinstance(LogInfo(msg='m'), LaunchDescriptionEntity)
    assert isinstance(LaunchDescription([]), LaunchDescriptionEntity)
    assert LaunchDescriptionEntity().visit(fresh()) is None
    with pytest.raises(NotImplementedError):
        LaunchDescriptionEntity().describe()
    assert 'LaunchDescription' in LaunchDescription([]).describe()


@pytest.mark.parametrize('module, name', [
    ('execute_process', 'ExecuteProcess'), ('declare_launch_argument', 'DeclareLaunchArgument'),
    ('opaque_function', 'OpaqueFunction'), ('shutdown_action', 'Shutdown'),
    ('push_launch_configurations', 'PushLaunchConfigurations'), ('unset_launch_configuration',
                                                                 'UnsetLaunchConfiguration'),
])
def test_each_action_has_launchs_module_too(module: str, name: str):
    """`launch.actions.<module>` holds the very class `launch.actions` exports."""
    actions = importlib.import_module('zros.launch.actions')
    assert getattr(importlib.import_module(f'zros.launch.actions.{module}'), name) is getattr(actions, name)
    assert importlib.import_module('zros.launch.launch_context').LaunchContext is LaunchContext


def test_reset_env_is_a_tag_in_yaml_and_xml(tmp_path):
    from zros.launch import resolve
    yaml_file = tmp_path / 'reset.launch.yaml'
    yaml_file.write_text('launch:\n- set_env: {name: RESET_PROBE, value: "1"}\n'
                         '- group:\n  - reset_env:\n  - log: {message: "in=$(env RESET_PROBE none)"}\n'
                         '- log: {message: "out=$(env RESET_PROBE none)"}\n')
    xml_file = tmp_path / 'reset.launch.xml'
    xml_file.write_text('<launch><set_env name="RESET_PROBE" value="1"/>'
                        '<group><reset_env/><log message="in=$(env RESET_PROBE none)"/></group>'
                        '<log message="out=$(env RESET_PROBE none)"/></launch>')
    for path in (yaml_file, xml_file):
        plan = resolve(str(path), environment={}, log_dir=str(tmp_path / 'log'))
        assert [effect.message for effect in plan.effects] == ['in=none', 'out=1']


def test_a_description_holds_any_entity_and_finds_arguments_under_conditions():
    """A user's LaunchDescriptionEntity is welcome in a description (and visits to nothing);
    `get_launch_arguments` notes which arguments only exist under a condition, including an
    entity's conditional sub-entities."""
    from zros.launch.conditions import IfCondition

    class WithConditional(LaunchDescriptionEntity):
        def describe_conditional_sub_entities(self):
            return [('when asked', [DeclareLaunchArgument('hidden')])]
    plain = DeclareLaunchArgument('plain')
    guarded = GroupAction([DeclareLaunchArgument('guarded')], condition=IfCondition('true'))
    description = LaunchDescription([LaunchDescriptionEntity(), plain, guarded, WithConditional()])
    found = {argument.name: argument._conditionally_included for argument in description.get_launch_arguments()}
    assert found == {'plain': False, 'guarded': True, 'hidden': True}
    context = LaunchContext(launch_arguments={'plain': 'x', 'guarded': 'y'}, environment={})
    visit_all([description], context)   # the plain entity visits to nothing
    assert context.configurations == {'plain': 'x', 'guarded': 'y'}
    assert not LaunchDescription().deprecated and LaunchDescription(deprecated_reason='old').deprecated
