"""launch_ros's actions as launch_ros code drives them by hand: the ROS scope kept in launch
configurations, a Node's expanded name, namespace and remappings, the LoadNode request of a
composable node, the TypeErrors of a bad `parameters=` / `remappings=`, and launch_ros's
module paths. No process is started."""
from __future__ import annotations

import importlib

import pytest

from zros.launch import LaunchContext
from zros.launch.actions import PopLaunchConfigurations, PushLaunchConfigurations
from zros.launch_ros.actions import Node, PushRosNamespace, SetParameter, SetRemap
from zros.launch_ros.actions.load_composable_nodes import get_composable_node_load_request
from zros.launch_ros.descriptions import ComposableNode


class BareContext:
    """What launch_ros's actions need of a context: launch configurations, nothing else."""

    def __init__(self) -> None:
        self.launch_configurations: dict = {}


def test_the_ros_scope_lives_in_launch_configurations_and_pops_with_them():
    context = LaunchContext()
    PushLaunchConfigurations().visit(context)
    PushRosNamespace('robot').visit(context)
    SetParameter('rate', 5).visit(context)
    SetRemap('scan', 'base_scan').visit(context)
    assert dict(context.launch_configurations) == {
        'ros_namespace': '/robot', 'global_params': [('rate', 5)], 'ros_remaps': [('scan', 'base_scan')]}
    PopLaunchConfigurations().visit(context)
    assert dict(context.launch_configurations) == {}


def test_a_set_inside_a_scope_does_not_change_the_list_saved_outside():
    context = LaunchContext()
    SetRemap('a', 'b').visit(context)
    PushLaunchConfigurations().visit(context)
    SetRemap('c', 'd').visit(context)
    PopLaunchConfigurations().visit(context)
    assert context.launch_configurations['ros_remaps'] == [('a', 'b')]


def test_actions_work_on_any_context_with_launch_configurations():
    context = BareContext()
    PushRosNamespace('robot').execute(context)
    PushRosNamespace('arm').execute(context)
    SetRemap('from', 'to').execute(context)
    assert context.launch_configurations == {'ros_namespace': '/robot/arm', 'ros_remaps': [('from', 'to')]}


@pytest.mark.parametrize('pushed, name, namespace, expected_ns, expected_name', [
    (None, 'n', 'ns', '/ns', '/ns/n'),
    ('robot', None, 'ns', '/robot/ns', '/robot/ns/<node_name_unspecified>'),
    ('robot', 'n', '/abs', '/abs', '/abs/n'),
    (None, 'n', None, '<node_namespace_unspecified>', '<node_namespace_unspecified>/n'),
    ('', None, None, '/', '/<node_name_unspecified>'),
])
def test_a_node_expands_its_name_under_the_pushed_namespace(pushed, name, namespace, expected_ns, expected_name):
    context = BareContext()
    if pushed is not None:
        PushRosNamespace(pushed).execute(context)
    node = Node(package='demo_nodes', executable='talker', name=name, namespace=namespace)
    with pytest.raises(RuntimeError):
        node.node_name   # noqa: B018 - only known once the node has been expanded
    node._perform_substitutions(context)
    assert node.expanded_node_namespace == expected_ns and node.node_name == expected_name
    assert node.is_node_name_fully_specified() is (name is not None and expected_ns.startswith('/'))


def test_a_nodes_remappings_follow_the_scopes():
    context = BareContext()
    SetRemap('a', 'b').execute(context)
    node = Node(package='demo_nodes', executable='talker', remappings=[('c', 'd')])
    node._perform_substitutions(context)
    assert node.expanded_remapping_rules == [('a', 'b'), ('c', 'd')]


@pytest.mark.parametrize('parameters, remappings', [
    ({'a': 1}, None), ('params.yaml', None), ([5.0], None), ([{5: 'x'}], None), ([{'a': [1, [2]]}], None),
    ([{'a': {1, 2}}], None), (None, {'a': 'b'}), (None, [{'a': 'b'}]),
])
def test_a_bad_parameters_or_remappings_value_is_a_type_error(parameters, remappings):
    with pytest.raises(TypeError):
        Node(package='demo_nodes', executable='talker', parameters=parameters, remappings=remappings)


def test_the_load_request_of_a_composable_node_has_the_scope_first():
    context = BareContext()
    PushRosNamespace('robot').execute(context)
    SetParameter('use_sim_time', True).execute(context)
    SetRemap('scan', 'base_scan').execute(context)
    description = ComposableNode(package='pkg', plugin='pkg::Camera', name='camera', namespace='front',
                                 parameters=[{'rate': 5.0, 'frame': {'id': 'cam'}}], remappings=[('image', 'raw')])
    request = get_composable_node_load_request(description, context)
    assert (request.package_name, request.plugin_name) == ('pkg', 'pkg::Camera')
    assert (request.node_name, request.node_namespace) == ('camera', '/robot/front')
    assert list(request.remap_rules) == ['scan:=base_scan', 'image:=raw']
    assert [(p.name, p.value.type) for p in request.parameters] == [('use_sim_time', 1), ('rate', 3), ('frame.id', 4)]


def test_a_composable_node_whose_condition_is_false_has_no_request():
    from zros.launch.conditions import IfCondition
    description = ComposableNode(package='pkg', plugin='pkg::Camera', condition=IfCondition('false'))
    assert get_composable_node_load_request(description, LaunchContext()) is None


def test_a_parameter_file_gives_the_composable_node_its_own_entries(tmp_path):
    path = tmp_path / 'params.yaml'
    path.write_text('/**:\n  ros__parameters: {a: 1}\n/ns/cam:\n  ros__parameters: {b: x}\n/other:\n'
                    '  ros__parameters: {c: 2}\n')
    description = ComposableNode(package='pkg', plugin='pkg::Camera', name='cam', namespace='ns', parameters=[path])
    request = get_composable_node_load_request(description, LaunchContext())
    assert [p.name for p in request.parameters] == ['a', 'b']


@pytest.mark.parametrize('module, name', [
    ('node', 'Node'), ('lifecycle_node', 'LifecycleNode'), ('composable_node_container', 'ComposableNodeContainer'),
    ('load_composable_nodes', 'LoadComposableNodes'), ('push_ros_namespace', 'PushROSNamespace'),
    ('set_parameter', 'SetParameter'), ('set_remap', 'SetRemap'), ('set_use_sim_time', 'SetUseSimTime'),
])
def test_each_action_has_launch_ros_module_path(module, name):
    import zros.launch_ros.actions as actions
    assert getattr(importlib.import_module(f'zros.launch_ros.actions.{module}'), name) is getattr(actions, name)


def test_set_ros_log_dir_goes_under_the_launch_environments_log_dir():
    from zros.launch_ros.actions import SetROSLogDir
    context = LaunchContext(environment={'ROS_LOG_DIR': '/var/log/ros'})
    SetROSLogDir('run1').visit(context)
    assert context.environment['ROS_LOG_DIR'] == '/var/log/ros/run1'
    SetROSLogDir('/elsewhere').visit(context)
    assert context.environment['ROS_LOG_DIR'] == '/elsewhere'
    context = LaunchContext(environment={'ROS_HOME': '/home/me/.ros'})
    SetROSLogDir('run2').visit(context)
    assert context.environment['ROS_LOG_DIR'] == '/home/me/.ros/log/run2'


def test_set_parameters_from_file_passes_the_file_before_the_nodes_own(tmp_path):
    from zros.launch.plan import GeneratedParams, ParamsFile
    from zros.launch_ros.actions import SetParametersFromFile
    path = tmp_path / 'common.yaml'
    path.write_text('/**:\n  ros__parameters: {rate: 10}\n')
    context = LaunchContext()
    SetParameter('a', 1).visit(context)
    SetParametersFromFile(str(path)).visit(context)
    assert context.launch_configurations['global_params'] == [('a', 1), str(path)]
    node = Node(package='demo_nodes', executable='talker', parameters=[{'b': 2}])
    sources = node.param_sources(context, '/talker')
    assert sources == [GeneratedParams({'/**': {'ros__parameters': {'a': 1}}}), ParamsFile(str(path)),
                       GeneratedParams({'/**': {'ros__parameters': {'b': 2}}})]


def test_the_launch_ros_scope_tags_parse(tmp_path):
    from zros.launch.files import load_launch_file
    from zros.launch_ros.actions import ROSTimer, SetParametersFromFile, SetROSLogDir
    path = tmp_path / 'f.launch.xml'
    path.write_text('<launch><set_ros_log_dir new_log_dir="run"/><set_parameters_from_file filename="p.yaml"/>'
                    '<ros_timer period="2.0"><log message="late"/></ros_timer></launch>')
    kinds = [type(action) for action in load_launch_file(str(path))]
    assert kinds == [SetROSLogDir, SetParametersFromFile, ROSTimer]


def test_a_ros_timer_is_on_sim_time_once_the_launch_sets_it_anywhere():
    from zros.launch.actions import LogInfo
    from zros.launch.plan import TimerEffect
    from zros.launch_ros.actions import ROSTimer, SetUseSimTime
    context = LaunchContext()
    context.begin_capture()
    for action in (ROSTimer(period=200.0, actions=[LogInfo(msg='late')]), SetUseSimTime(True)):
        visit_all([action], context)
    [timer] = [effect for effect in context.end_capture() if isinstance(effect, TimerEffect)]
    assert timer.period == 200.0 and timer.sim_time()


def visit_all(actions, context) -> None:
    for action in actions:
        visit_all(action.visit(context) or [], context)


def test_matches_node_name_compares_the_executed_nodes_full_name():
    from zros.launch_ros.events import matches_node_name
    node = Node(package='demo_nodes', executable='talker', name='talker', namespace='')
    matcher = matches_node_name('talker')
    assert not matcher(node)             # not executed: no name yet
    node._perform_substitutions(LaunchContext())
    assert matcher(node) and matches_node_name('/talker')(node) and not matches_node_name('/ns/talker')(node)


def test_lifecycle_transition_chains_each_transition_on_the_goal_of_the_one_before():
    from zros.launch.actions import EmitEvent, RegisterEventHandler
    from zros.launch.lifecycle import StateTransition
    from zros.launch_ros.actions import LifecycleTransition
    with pytest.raises(ValueError):
        LifecycleTransition(lifecycle_node_names=['a'], transition_ids=[])
    with pytest.raises(ValueError):
        LifecycleTransition(lifecycle_node_names=[], transition_ids=[1])
    actions = LifecycleTransition(lifecycle_node_names=['a'], transition_ids=[1, '3']).execute(LaunchContext())
    assert [type(action) for action in actions] == [RegisterEventHandler, EmitEvent]
    assert actions[1].event.transition_id == 1
    handler = actions[0].event_handler

    class Named:
        node_name = '/a'
    configured = StateTransition(Named(), 'transition_success', 'configuring', 'inactive', 'a-1')
    activated = StateTransition(Named(), 'transition_success', 'activating', 'active', 'a-1')
    assert handler.matcher(configured) and not handler.matcher(activated)
    with pytest.raises(ValueError):
        LifecycleTransition(lifecycle_node_names=['a'], transition_ids=['x']).execute(LaunchContext())


def test_set_parameter_shows_its_value_as_launch_ros_does():
    from zros.launch.substitutions import TextSubstitution
    from zros.launch.utilities import perform_substitutions
    text = SetParameter('name', 'value')
    assert perform_substitutions(LaunchContext(), text.value) == 'value'
    assert all(isinstance(s, TextSubstitution) for s in text.value)
    assert SetParameter('rate', 5).value == 5


def test_a_named_container_counts_as_a_node_of_the_launch():
    from zros.launch_ros.actions import ComposableNodeContainer
    from zros.launch_ros.utilities import get_node_name_count
    context = LaunchContext()
    container = ComposableNodeContainer(package='rclcpp_components', executable='component_container',
                                        name='box', namespace='ns', composable_node_descriptions=[])
    container.visit(context)
    assert get_node_name_count(context, '/ns/box') == 1 and container.node_name == '/ns/box'


def test_a_component_is_counted_under_the_full_name_its_container_would_report():
    """Unlike a Node, a component always has a full name: '/' when no namespace is given, and
    the component's own node name (its executable's) when no name is."""
    from zros.launch_ros.actions import ComposableNodeContainer
    context = LaunchContext()
    container = ComposableNodeContainer(
        package='rclcpp_components', executable='component_container', name='box', namespace='/ns',
        composable_node_descriptions=[
            ComposableNode(package='composition', plugin='composition::Listener'),
            ComposableNode(package='composition', plugin='composition::Talker', name='t'),
            ComposableNode(package='composition', plugin='composition::Talker', name='box', namespace='ns')])
    context.begin_capture()
    try:
        for node in container.execute(context):
            node.execute(context)
    finally:
        effects = context.end_capture()
    assert dict(context.node_names) == {'/ns/box': 2, '/listener': 1, '/t': 1}
    assert any('at least 2 nodes with the name /ns/box' in getattr(e, 'message', '') for e in effects)
