"""Launch files parsed and resolved, without starting anything: every tag, every substitution
and every error path (each error must read `file:line: <tag>: <key>: reason`)."""
from __future__ import annotations

import os
import re
import sys
import textwrap
from pathlib import Path

import pytest
import yaml

from zros.launch import LaunchError, LaunchFileError, resolve
from zros.launch.context import LaunchContext
from zros.launch.description import declared_arguments, parse_launch_arguments
from zros.launch.entity import Entity, Scalar, load_launch_entities, load_yaml
from zros.ament_index_python.packages import get_package_share_path
from zros.launch.packages import configs_directory, find_launch_file
from zros.launch.plan import GeneratedParams, LogMessage, ParamsFile, ProcessSpec, ShutdownEffect, TimerEffect
from zros.launch.template import Call, SUBSTITUTIONS, SubstitutionError, describe, evaluate_expression, parse, perform

REPO = Path(__file__).resolve().parents[2]
PY = sys.executable


# -- helpers ------------------------------------------------------------------------------------
@pytest.fixture
def write(tmp_path: Path):
    """`write('a.launch.yaml', text)` -> path of a dedented file in tmp_path."""
    def write_file(name: str, text: str) -> Path:
        path = tmp_path / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(textwrap.dedent(text).lstrip('\n'))
        return path
    return write_file


def plan_maker(write, tmp_path: Path, file_name: str):
    """`make(text, name=value...)` -> the resolved Plan of `text` written as `file_name`."""
    def make(text: str, **arguments: str):
        path = write(file_name, text)
        return resolve(str(path), launch_arguments=arguments, log_dir=str(tmp_path / 'log'))
    return make


@pytest.fixture
def plan_of(write, tmp_path: Path):
    """`plan_of(yaml_text, name:=value...)` -> the resolved Plan of a one-file launch."""
    return plan_maker(write, tmp_path, 'test.launch.yaml')


def processes(plan) -> list[ProcessSpec]:
    return [e for e in plan.effects if isinstance(e, ProcessSpec)]


def only_process(plan) -> ProcessSpec:
    found = processes(plan)
    assert len(found) == 1, plan.effects
    return found[0]


def ros_part(spec: ProcessSpec) -> list[str]:
    cmd = list(spec.cmd_head)
    return cmd[cmd.index('--ros-args') + 1:] if '--ros-args' in cmd else []


def error_of(make, *args, **kwargs) -> str:
    with pytest.raises(LaunchError) as info:
        make(*args, **kwargs)
    text = str(info.value)
    assert '\n' not in text
    return text


def assert_located(message: str, path_end: str, line: int, tag: str, key: str | None = None) -> None:
    """`message` is `<dir>/<path_end>:<line>: <tag>: [<key>: ]reason`."""
    prefix = f'{path_end}:{line}: {tag}: ' + (f'{key}: ' if key else '')
    assert re.match(r'^[^:]*' + re.escape(prefix), message), f'{message!r} does not start with ...{prefix!r}'


class Ctx:
    """A minimal substitution context."""

    def __init__(self, **configurations: str) -> None:
        self.context = LaunchContext(launch_arguments=configurations, environment={'HOME': '/home/x', 'PATH': os.environ['PATH']},
                                     log_dir='/tmp/zros-log-dir')
        self.context.enter_file(str(REPO / 'configs' / 'talker_listener.launch.yaml'), None)

    def __call__(self, text: str) -> str:
        return perform(parse(text), self.context)


# -- entity: YAML with line numbers, typed accessor -------------------------------------------
def test_yaml_keeps_lines_of_keys_values_and_items(write):
    path = write('x.yaml', '''
        launch:
        - node:
            pkg: demo_nodes
            exec: talker
        - arg: {name: a}
        ''')
    doc = load_yaml(path)
    node = doc['launch'][0]['node']
    assert node.key_lines['exec'] == 4 and node.value_lines['pkg'] == 3
    assert doc['launch'].item_lines == [2, 5]
    entities = load_launch_entities(path)
    assert [(e.type_name, e.line) for e in entities] == [('node', 2), ('arg', 5)]


def test_entity_get_attr_types(write):
    path = write('x.yaml', '''
        launch:
        - t: {s: text, i: 3, f: 2.5, b: true, l: [a, 1], m: [{x: 1}], n: 7}
        ''')
    entity, = load_launch_entities(path)
    assert entity.get_attr('s') == 'text'
    assert entity.get_attr('i', data_type=int) == 3
    assert entity.get_attr('i', data_type=float) == 3.0
    assert entity.get_attr('f', data_type=float) == 2.5
    assert entity.get_attr('b', data_type=bool) is True
    assert entity.get_attr('b', data_type=Scalar) == 'true'
    assert entity.get_attr('n', data_type=Scalar) == '7'
    assert entity.get_attr('l', data_type=list[str]) == ['a', '1']
    items = entity.get_attr('m', data_type=list[Entity])
    assert items[0].type_name == 'm' and items[0].get_attr('x', data_type=int) == 1
    assert entity.get_attr('missing', optional=True) is None
    with pytest.raises(LaunchFileError, match=r"x.yaml:2: t: i: expected a string, got an int 3"):
        entity.get_attr('i')
    with pytest.raises(LaunchFileError, match=r"x.yaml:2: t: s: expected a bool"):
        entity.get_attr('s', data_type=bool)
    with pytest.raises(LaunchFileError, match=r"x.yaml:2: t: missing required attribute 'nope'"):
        entity.get_attr('nope')
    entity.assert_complete()   # every key was read

def test_entity_unknown_key_names_known_ones(write):
    path = write('x.yaml', 'launch:\n- t: {good: 1, bad: 2}\n')
    entity, = load_launch_entities(path)
    entity.get_attr('good', data_type=int)
    entity.get_attr('other', optional=True)
    with pytest.raises(LaunchFileError) as info:
        entity.assert_complete()
    assert str(info.value).endswith("x.yaml:2: t: bad: unknown key 'bad' of `t` (known keys: good, other)")


# -- substitution grammar -----------------------------------------------------------------------
def test_grammar_text_calls_quotes_nesting_and_escapes():
    assert parse('plain') == ('plain',)
    assert parse('') == ()
    assert parse('a $(var x) b') == ('a ', Call('var', (('x',),)), ' b')
    assert parse("$(var 'a b' \"c d\")") == (Call('var', (('a b',), ('c d',))),)
    assert parse('$(var x $(env Y))') == (Call('var', (('x',), (Call('env', (('Y',),)),))),)
    assert parse("$(eval '$(var n) + 1')") == (Call('eval', ((Call('var', (('n',),)), ' + 1'),)),)
    assert parse(r'cost \$(var x) $5') == ('cost $(var x) $5',)
    assert parse(r"$(var 'it\'s')") == (Call('var', (("it's",),)),)
    assert parse('$(dirname)/x') == (Call('dirname', ()), '/x')


def test_a_call_with_a_quote_inside_a_quoted_argument_is_written_back_as_it_parses():
    """Inside quoted text the other quote is plain text (launch's grammar), so describe() quotes
    a nested call's argument with the enclosing quote, escaped (`--print`, `--show-args`)."""
    template = (Call('var', ((Call('var', (("'",),)), ' x'),)),)
    assert describe(template) == """$(var '$(var '\\'') x')"""
    assert parse(describe(template)) == template


def test_inside_quotes_the_other_quote_is_text_also_in_a_nested_call():
    """launch's grammar: `$(env "a_$(var 'b')")` gives var the name `'b'`, quotes and all."""
    assert parse("""$(env "a_$(var 'b')")""") == (Call('env', (('a_', Call('var', (("'b'",),))),)),)
    assert parse("""$(env 'a_$(var "b")')""") == (Call('env', (('a_', Call('var', (('"b"',),))),)),)
    assert parse("""$(env "$(var "b c")")""") == (Call('env', ((Call('var', (('b c',),)),),)),)


@pytest.mark.parametrize('text, fragment', [
    ('$(var x', "unterminated substitution '$(var': missing ')'"),
    ('$(nope x)', "unknown substitution 'nope'"),
    ('$(var)', "'$(var)' takes 1 to 2 arguments, got 0"),
    ('$(dirname x)', "'$(dirname)' takes 0 arguments, got 1"),
    ("$(var 'x)", 'unterminated'),
    ('$( var x)', "expected a substitution name after '$('"),
])
def test_grammar_errors(text, fragment):
    with pytest.raises(SubstitutionError, match=re.escape(fragment)):
        parse(text)


# -- every substitution -----------------------------------------------------------------------
def test_var_and_env(monkeypatch):
    ctx = Ctx(topic='news')
    assert ctx('$(var topic)') == 'news'
    assert ctx('$(var missing fallback)') == 'fallback'
    with pytest.raises(SubstitutionError, match="launch configuration 'missing' is not set"):
        ctx('$(var missing)')
    assert ctx('$(env HOME)') == '/home/x'
    assert ctx('$(env NOPE_NOT_SET dflt)') == 'dflt'
    assert ctx('$(optenv NOPE_NOT_SET)') == ''
    with pytest.raises(SubstitutionError, match="environment variable 'NOPE_NOT_SET' does not exist"):
        ctx('$(env NOPE_NOT_SET)')


def test_dirname_filename_log_dir():
    ctx = Ctx()
    assert ctx('$(dirname)') == str(REPO / 'configs')
    assert ctx('$(filename)') == str(REPO / 'configs' / 'talker_listener.launch.yaml')
    assert ctx('$(log_dir)') == ctx('$(launch_log_dir)') == '/tmp/zros-log-dir'


def test_find_pkg_share_rule():
    ctx = Ctx()
    assert ctx('$(find-pkg-share demo_nodes)') == str((REPO / 'nodes' / 'demo_nodes').resolve())
    assert ctx('$(find-pkg-share configs)') == str(configs_directory())
    assert Path(ctx('$(find-pkg-share zros)/configs/params/talker.yaml')).is_file()
    assert Path(ctx('$(find-pkg-share configs)/params/talker.yaml')).is_file()
    assert ctx('$(find-pkg-prefix demo_nodes)') == str((REPO / 'nodes').resolve())
    with pytest.raises(SubstitutionError, match="package 'no_such_pkg' not found"):
        ctx('$(find-pkg-share no_such_pkg)')
    assert find_launch_file('zros', 'talker_listener.launch.yaml') == \
        configs_directory() / 'talker_listener.launch.yaml'
    assert find_launch_file('configs', 'params_demo.launch.yaml').is_file()
    with pytest.raises(LaunchError, match="launch file 'nope.yaml' not found in package 'demo_nodes'"):
        find_launch_file('demo_nodes', 'nope.yaml')
    assert get_package_share_path('zros') == configs_directory().parent


def test_eval_is_python_with_math_and_nothing_dangerous():
    ctx = Ctx(n='200', flag='true')
    assert ctx("$(eval '1 + 2 * 3')") == '7'
    assert ctx("$(eval 'sqrt(16) + math.pi - pi')") == '4.0'
    assert ctx("$(eval '$(var n) == 200 and $(var flag)' math)") == 'True'   # true/false are names too
    assert ctx("$(eval \"'$(var flag)' == 'true'\")") == 'True'
    assert ctx("$(eval 'max(1, 5)')") == '5'
    for bad in ("().__class__", "__import__('os')", "open('/etc/passwd')", "lambda: 1"):
        with pytest.raises(SubstitutionError):
            evaluate_expression(bad)
    with pytest.raises(SubstitutionError, match="cannot import module 'no_such_module_zz'"):
        evaluate_expression('1', 'no_such_module_zz')
    with pytest.raises(SubstitutionError, match='invalid Python expression'):
        evaluate_expression('1 +')
    with pytest.raises(SubstitutionError, match='ZeroDivisionError'):
        evaluate_expression('1 / 0')


def test_eval_has_the_modules_it_names_and_a_missing_name_is_a_name_error():
    assert evaluate_expression('sys.maxsize > 0 and isfinite(1)', ' math,sys ') == 'True'
    assert evaluate_expression('ceil(1.2)') == '2'          # math by default, also bare
    for modules in ('', 'sys'):                              # named modules only: no math
        with pytest.raises(NameError, match="name 'ceil' is not defined"):
            evaluate_expression('ceil(1.2)', modules)
    with pytest.raises(SubstitutionError):                   # also the launch error for --print / files
        evaluate_expression('math.pi', '')
    assert Ctx()("$(eval 'len(sys.argv) >= 0' sys)") == 'True'


def test_anon_is_stable_per_launch_and_a_valid_name():
    ctx = Ctx()
    first = ctx('$(anon my-node)')
    assert first == ctx('$(anon my-node)') != ctx('$(anon other)')
    assert re.fullmatch(r'my_node_\w+_\d+_\d+', first)   # launch's name_<host>_<pid>_<random>
    assert Ctx()('$(anon my-node)') != first


def test_boolean_substitutions():
    ctx = Ctx(yes='true', no='0')
    assert ctx('$(not $(var yes))') == 'false'
    assert ctx('$(not $(var no))') == 'true'
    assert ctx('$(and $(var yes) 1)') == 'true'
    assert ctx('$(and $(var yes) $(var no))') == 'false'
    assert ctx('$(or $(var no) false)') == 'false'
    assert ctx('$(or $(var no) True)') == 'true'
    assert ctx('$(all true true 1)') == 'true' and ctx('$(any false 0 1)') == 'true'
    assert ctx('$(equals 1 1.0)') == 'true'
    assert ctx('$(equals True true)') == 'true'
    assert ctx('$(equals abc abd)') == 'false'
    assert ctx('$(not-equals abc abd)') == 'true'
    assert ctx('$(if $(var yes) on off)') == 'on'
    assert ctx('$(if $(var no) on)') == ''
    with pytest.raises(SubstitutionError, match="'maybe' is not a boolean"):
        ctx('$(not maybe)')


def test_find_exec_and_file_content(tmp_path):
    ctx = Ctx()
    assert ctx('$(find-exec sh)').endswith('/sh')
    with pytest.raises(SubstitutionError, match='not found on PATH'):
        ctx('$(find-exec no-such-program-zz)')
    (tmp_path / 'f.txt').write_text('content')
    assert ctx(f'$(file-content {tmp_path}/f.txt)') == 'content'


def test_every_registered_substitution_is_tested():
    tested = {'var', 'env', 'optenv', 'dirname', 'filename', 'log_dir', 'launch_log_dir', 'find-pkg-share',
              'find-pkg-prefix', 'eval', 'command', 'anon', 'not', 'and', 'or', 'all', 'any', 'equals',
              'not-equals', 'if', 'find-exec', 'file-content', 'param', 'path-join'}
    assert set(SUBSTITUTIONS) == tested


def test_param_lazy_defaults_and_path_join():
    ctx = Ctx()
    for pair in [('rate', 10), ('flag', True), ('rate', 20)]:
        ctx.context.ros.add_param(pair)
    assert ctx('$(param rate)') == '20'                    # what the next node would get
    assert ctx('$(param flag)') == 'true'
    assert ctx('$(param missing 5)') == '5'
    with pytest.raises(SubstitutionError, match="parameter 'missing' was not set with set_parameter"):
        ctx('$(param missing)')
    # a default is evaluated only when it is needed
    assert Ctx(x='set')('$(var x $(var unset))') == 'set'
    assert ctx('$(if true yes $(var unset))') == 'yes'
    with pytest.raises(SubstitutionError, match="unknown substitution 'path-join'"):
        parse('$(path-join a b)')                         # Python-only (PathJoinSubstitution)
    assert perform((Call('path-join', (('a',), ('b',), ('c.yaml',))),), ctx.context) == 'a/b/c.yaml'


# -- tags -------------------------------------------------------------------------------------
def test_arg_default_given_choices_and_description(plan_of, write):
    text = '''
        launch:
        - arg: {name: topic, default: chatter, description: where}
        - arg: {name: mode, default: fast, choice: [{value: fast}, {value: slow}]}
        - arg: {name: count, default: 3}
        - log: {message: "$(var topic) $(var mode) $(var count)"}
        '''
    plan = plan_of(text)
    assert plan.effects == [LogMessage('INFO', 'chatter fast 3', plan.effects[0].origin)]
    assert plan.arguments == {'topic': 'chatter', 'mode': 'fast', 'count': '3'}
    assert plan_of(text, topic='news', mode='slow').effects[0].message == 'news slow 3'
    args = {a.name: a for a in declared_arguments(str(write('test.launch.yaml', text)))}
    assert args['topic'].description == 'where' and args['topic'].default == 'chatter'
    assert args['mode'].choices == ('fast', 'slow')


def test_let_sets_a_configuration(plan_of):
    plan = plan_of('''
        launch:
        - let: {name: greeting, value: "hi $(env NOPE_UNSET you)"}
        - log: {message: $(var greeting)}
        ''')
    assert plan.effects[0].message == 'hi you'


def test_node_command_line(plan_of):
    spec = only_process(plan_of('''
        launch:
        - arg: {name: topic, default: news}
        - node:
            pkg: demo_nodes
            exec: talker
            name: my_talker
            namespace: robot
            args: "--flag 'two words'"
            ros_args: "--log-level debug"
            remap:
            - {from: chatter, to: $(var topic)}
            - {from: /a, to: /b}
        '''))
    assert spec.cmd_head[:6] == (sys.executable, '-m', 'zros', 'run', 'demo_nodes', 'talker')
    # as launch_ros: the user's ROS arguments in a --ros-args section of their own, before the launch's
    assert spec.cmd_head[6:12] == ('--flag', 'two words', '--ros-args', '--log-level', 'debug', '--ros-args')
    assert spec.cmd_head[12:] == ('-r', '__node:=my_talker', '-r', '__ns:=/robot', '-r', 'chatter:=news',
                                  '-r', '/a:=/b')
    assert spec.label == 'talker' and spec.node.name == 'my_talker' and spec.node.namespace == '/robot'
    assert spec.output == 'log' and not spec.respawn and spec.sigterm_timeout == 5.0


def test_node_without_ros_arguments_has_no_ros_args_section(plan_of):
    spec = only_process(plan_of('launch:\n- node: {pkg: demo_nodes, exec: listener, exec_name: ears}\n'))
    assert '--ros-args' not in spec.cmd_head and spec.label == 'ears' and spec.node.namespace == '/'


def test_node_process_options(plan_of):
    spec = only_process(plan_of('''
        launch:
        - arg: {name: again, default: 'true'}
        - node:
            pkg: demo_nodes
            exec: talker
            output: both
            respawn: $(var again)
            respawn_delay: 0.5
            respawn_max_retries: 2
            sigterm_timeout: 1
            sigkill_timeout: '2.5'
            on_exit: shutdown
            emulate_tty: true
            launch-prefix: nice -n 5
            env: [{name: ZZ_X, value: 1}]
        '''))
    assert (spec.output, spec.respawn, spec.respawn_delay, spec.respawn_max_retries) == ('both', True, 0.5, 2)
    assert (spec.sigterm_timeout, spec.sigkill_timeout, spec.on_exit_shutdown) == (1.0, 2.5, True)
    assert spec.cmd_head[:3] == ('nice', '-n', '5')
    assert ('ZZ_X', '1') in spec.env


def test_node_parameters_in_order(plan_of, write, tmp_path):
    params = write('p.yaml', '/**:\n  ros__parameters:\n    from_file: 1\n')
    spec = only_process(plan_of(f'''
        launch:
        - arg: {{name: text, default: hello}}
        - set_parameter: {{name: global_one, value: 1}}
        - node:
            pkg: demo_nodes
            exec: param_talker
            param:
            - {{name: published_text, value: $(var text)}}
            - {{name: quoted, value: "42"}}
            - {{name: forced, value: "42", type: str}}
            - {{name: ratio, value: 0.5}}
            - {{name: list, value: [a, $(var text)]}}
            - name: limits
              param:
              - {{name: max, value: 10}}
              - name: deeper
                param: [{{name: enabled, value: true}}]
            - from: {params}
            - {{name: after_file, value: x}}
        '''))
    first, file_source, last = spec.params
    assert first == GeneratedParams({'/**': {'ros__parameters': {
        'global_one': 1, 'published_text': 'hello', 'quoted': '42', 'forced': '42', 'ratio': 0.5,
        'list': ['a', 'hello'], 'limits': {'max': 10, 'deeper': {'enabled': True}}}}})
    assert file_source == ParamsFile(str(params.resolve()))
    assert last.document == {'/**': {'ros__parameters': {'after_file': 'x'}}}
    paths = spec.generated_params_paths(tmp_path / 'log' / 'params', 'param_talker-1')
    assert paths == [str(tmp_path / 'log/params/param_talker-1.yaml'), str(params.resolve()),
                     str(tmp_path / 'log/params/param_talker-1-2.yaml')]
    cmd = spec.command(paths)
    assert cmd.count('--params-file') == 3
    assert yaml.safe_load(first.to_yaml()) == first.document


def test_param_from_with_allow_substs(plan_of, write):
    write('subst.yaml', '/**:\n  ros__parameters:\n    text: "$(var word)"\n')
    spec = only_process(plan_of('''
        launch:
        - arg: {name: word, default: hi}
        - node:
            pkg: demo_nodes
            exec: param_talker
            param: [{from: subst.yaml, allow_substs: true}]
        '''))
    assert spec.params == (GeneratedParams({'/**': {'ros__parameters': {'text': 'hi'}}}),)


def test_executable(plan_of, tmp_path):
    plan = plan_of(f'''
        launch:
        - arg: {{name: msg, default: two words}}
        - executable: {{cmd: "echo '$(var msg)' x", name: shout, cwd: {tmp_path}}}
        - executable: {{cmd: "echo $HOME | cat", shell: true}}
        ''')
    echo, shell = processes(plan)
    assert echo.cmd_head == ('echo', 'two words', 'x') and echo.label == 'shout' and echo.cwd == str(tmp_path)
    assert shell.cmd_head == ('/bin/sh', '-c', 'echo $HOME | cat') and shell.label == 'echo'
    assert shell.shell_text == 'echo $HOME | cat' and shell.node is None


def test_include_with_arguments_and_relative_path(plan_of, write):
    write('sub/inner.launch.yaml', '''
        launch:
        - arg: {name: who}
        - arg: {name: greeting, default: hello}
        - log: {message: "$(var greeting) $(var who) from $(filename)"}
        ''')
    plan = plan_of('''
        launch:
        - include:
            file: sub/inner.launch.yaml
            arg: [{name: who, value: world}]
        - log: {message: "after: $(var who)"}
        ''')
    inner, after = plan.effects
    assert inner.message.startswith('hello world from ') and inner.message.endswith('sub/inner.launch.yaml')
    assert after.message == 'after: world'  # an include is not a scope, as in ROS 2


def test_group_scoping_forwarding_and_keep(plan_of):
    plan = plan_of('''
        launch:
        - let: {name: a, value: outer}
        - set_env: {name: ZZ_GROUP, value: outer}
        - group:
          - let: {name: a, value: inner}
          - set_env: {name: ZZ_GROUP, value: inner}
          - log: {message: "in: $(var a) $(env ZZ_GROUP)"}
        - log: {message: "scoped: $(var a) $(env ZZ_GROUP)"}
        - group:
            scoped: false
            children:
            - let: {name: a, value: leaked}
        - log: {message: "unscoped: $(var a)"}
        - group:
            forwarding: false
            keep: [{name: kept, value: $(var a)}]
            children:
            - log: {message: "fresh: $(var a none) $(var kept)"}
        - log: {message: "after: $(var a)"}
        ''')
    assert [e.message for e in plan.effects] == [
        'in: inner inner', 'scoped: outer outer', 'unscoped: leaked', 'fresh: none leaked', 'after: leaked']


def test_push_ros_namespace_both_spellings_and_scopes(plan_of):
    plan = plan_of('''
        launch:
        - group:
          - push_ros_namespace: {namespace: fleet}
          - push-ros-namespace: {namespace: robot1}
          - node: {pkg: demo_nodes, exec: talker}
          - node: {pkg: demo_nodes, exec: talker, namespace: cam}
          - node: {pkg: demo_nodes, exec: talker, namespace: /absolute}
        - node: {pkg: demo_nodes, exec: talker}
        ''')
    assert [p.node.namespace for p in processes(plan)] == ['/fleet/robot1', '/fleet/robot1/cam', '/absolute', '/']


def test_environment_tags(plan_of, monkeypatch):
    monkeypatch.setenv('ZZ_PATHLIKE', '/a')
    monkeypatch.setenv('ZZ_GONE', 'x')
    spec = only_process(plan_of('''
        launch:
        - set_env: {name: ZZ_SET, value: 1}
        - unset_env: {name: ZZ_GONE}
        - append_env: {name: ZZ_PATHLIKE, value: /b}
        - append_env: {name: ZZ_PATHLIKE, value: /z, prepend: true}
        - append_env: {name: ZZ_NEW, value: first, separator: ','}
        - append_env: {name: ZZ_NEW, value: second, separator: ','}
        - executable: {cmd: 'sh -c "echo $(env ZZ_SET)"'}
        '''))
    env = dict(spec.env)
    assert env['ZZ_SET'] == '1' and env['ZZ_GONE'] is None
    assert env['ZZ_PATHLIKE'] == os.pathsep.join(['/z', '/a', '/b'])
    assert env['ZZ_NEW'] == 'first,second'
    assert spec.cmd_head == ('sh', '-c', 'echo 1')


def test_ros_scope_tags(plan_of):
    plan = plan_of('''
        launch:
        - group:
          - set_parameter: {name: rate, value: 5}
          - set_remap: {from: chatter, to: global_topic}
          - set_use_sim_time: {value: true}
          - node: {pkg: demo_nodes, exec: talker, remap: [{from: chatter, to: own}]}
        - node: {pkg: demo_nodes, exec: talker}
        ''')
    scoped, outside = processes(plan)
    assert scoped.params == (GeneratedParams({'/**': {'ros__parameters': {'rate': 5, 'use_sim_time': True}}}),)
    assert ros_part(scoped) == ['-r', 'chatter:=global_topic', '-r', 'chatter:=own']
    assert outside.params == () and '--ros-args' not in outside.cmd_head


def test_log_timer_shutdown(plan_of):
    plan = plan_of('''
        launch:
        - log: {message: starting, level: warn}
        - timer:
            period: 1.5
            children:
            - log: {message: later}
            - executable: {cmd: 'true'}
        - shutdown: {reason: done}
        ''')
    log, timer, shutdown = plan.effects
    assert log == LogMessage('WARNING', 'starting', log.origin)
    assert isinstance(timer, TimerEffect) and timer.period == 1.5
    assert timer.effects[0].message == 'later' and isinstance(timer.effects[1], ProcessSpec)
    assert shutdown == ShutdownEffect('done', shutdown.origin)
    text = plan.describe()
    assert 'after 1.5 s:' in text and 'process [true' in text and 'shutdown: done' in text


def test_timer_with_zero_period(plan_of):
    plan = plan_of('''
        launch:
        - timer: {period: 0, children: [{log: {message: now}}]}
        ''')
    assert plan.effects[0].effects[0].message == 'now'


@pytest.mark.parametrize('tag', [
    "log: {message: x, IF}",
    "let: {name: v, value: x, IF}",
    "arg: {name: v, default: x, IF}",
    "set_env: {name: ZZ_V, value: x, IF}",
    "unset_env: {name: ZZ_V, IF}",
    "append_env: {name: ZZ_V, value: x, IF}",
    "set_parameter: {name: v, value: x, IF}",
    "set_remap: {from: a, to: b, IF}",
    "set_use_sim_time: {value: true, IF}",
    "push_ros_namespace: {namespace: x, IF}",
    "node: {pkg: demo_nodes, exec: talker, IF}",
    "executable: {cmd: 'true', IF}",
    "include: {file: inc.launch.yaml, IF}",
    "group: {children: [{log: {message: x}}], IF}",
    "timer: {period: 1, children: [{log: {message: x}}], IF}",
    "shutdown: {IF}",
])
def test_if_and_unless_on_every_tag(plan_of, write, tag):
    write('inc.launch.yaml', 'launch:\n- log: {message: included}\n')
    head = "launch:\n- arg: {name: flag, default: 'false'}\n- "
    tail = '\n- node: {pkg: demo_nodes, exec: listener}\n'   # something that depends on scope tags
    skipped = plan_of(head + tag.replace('IF', "if: '$(var flag)'") + tail, flag='false')
    kept = plan_of(head + tag.replace('IF', "unless: '$(not $(var flag))'") + tail, flag='true')
    assert len(kept.effects) >= len(skipped.effects)
    assert kept.effects != skipped.effects or tag.startswith(('let', 'arg', 'unset_env'))
    with pytest.raises(LaunchFileError, match="'if' and 'unless' cannot be used together"):
        plan_of(head + tag.replace('IF', "if: 'true', unless: 'false'"))


def test_launch_arguments_from_the_command_line():
    assert parse_launch_arguments(['a:=1', 'b:=x:=y', 'a:=2']) == {'a': '2', 'b': 'x:=y'}
    with pytest.raises(LaunchError, match="name:=value, got 'oops'"):
        parse_launch_arguments(['oops'])


def test_builtin_configurations_set_timeouts_and_prefix(plan_of):
    spec = only_process(plan_of('launch:\n- executable: {cmd: "true"}\n', sigterm_timeout='1', sigkill_timeout='2'))
    assert (spec.sigterm_timeout, spec.sigkill_timeout) == (1.0, 2.0)


def test_shipped_launch_files_resolve():
    for name in ('talker_listener', 'remap_demo', 'params_demo', 'namespaced', 'multi_robot'):
        plan = resolve(str(REPO / 'configs' / f'{name}.launch.yaml'), log_dir='/tmp/x')
        assert processes(plan) or plan.effects
    multi = resolve(str(REPO / 'configs' / 'multi_robot.launch.yaml'), log_dir='/tmp/x')
    assert [p.node.display_name() for p in processes(multi)] == [
        '/fleet/robot1/talker', '/fleet/robot1/listener', '/fleet/robot2/talker', '/fleet/robot2/listener']
    demo = resolve(str(REPO / 'configs' / 'talker_listener.launch.yaml'), launch_arguments={'topic': 'news'})
    assert all(p.output == 'screen' and ros_part(p) == ['-r', 'chatter:=news'] for p in processes(demo))


# -- errors: file:line: tag: key: reason -------------------------------------------------------
def test_error_yaml_syntax(plan_of):
    message = error_of(plan_of, 'launch:\n- node: {pkg: demo_nodes, exec: talker\n')
    assert re.search(r'test\.launch\.yaml:3: invalid YAML: ', message), message


def test_error_not_a_launch_file(plan_of):
    assert "a launch file must be a mapping with a 'launch:' list" in error_of(plan_of, '- node: {}\n')
    assert "unknown top-level key 'lunch'" in error_of(plan_of, 'launch: []\nlunch: []\n')
    assert 'exactly one key, the tag' in error_of(plan_of, 'launch:\n- {node: {}, arg: {}}\n')


def test_error_unknown_tag(plan_of):
    message = error_of(plan_of, 'launch:\n- log: {message: x}\n- frobnicate: {a: 1}\n')
    assert_located(message, 'test.launch.yaml', 3, 'frobnicate')
    assert 'unknown tag (known tags: append_env, arg, executable, group' in message


def test_error_unknown_key(plan_of):
    message = error_of(plan_of, 'launch:\n- node:\n    pkg: demo_nodes\n    exec: talker\n    colour: red\n')
    assert_located(message, 'test.launch.yaml', 5, 'node', 'colour')
    assert "unknown key 'colour' of `node` (known keys: args, " in message
    nested = error_of(plan_of, 'launch:\n- node:\n    pkg: demo_nodes\n    exec: talker\n    remap:\n'
                               '    - {from: a, to: b, via: c}\n')
    assert_located(nested, 'test.launch.yaml', 6, 'remap', 'via')


@pytest.mark.parametrize('attribute, expected', [
    ('respawn: 3', 'respawn: expected a bool (true or false), got int 3'),
    ("respawn: 'maybe'", "respawn: expected a bool (true or false), got string 'maybe'"),
    ('respawn_delay: soon', "respawn_delay: expected a number, got string 'soon'"),
    ('respawn_delay: -1', 'respawn_delay: expected a non-negative number, got -1'),
    ('respawn_max_retries: 1.5', 'respawn_max_retries: expected an int, got float 1.5'),
    ('name: [a, b]', 'name: expected a string, got a list'),
    ('output: loud', "output: expected one of log, screen, both, own_log, got 'loud'"),
    ('on_exit: restart', "on_exit: the only supported action is 'shutdown', got 'restart'"),
    ('remap: 7', 'remap: expected a list of mappings, got an int 7'),
])
def test_error_wrong_attribute_type(plan_of, attribute, expected):
    message = error_of(plan_of, f'launch:\n- node:\n    pkg: demo_nodes\n    exec: talker\n    {attribute}\n')
    assert_located(message, 'test.launch.yaml', 5, 'node')
    assert message.split('node: ', 1)[1] == expected


def test_error_missing_required_attribute(plan_of):
    message = error_of(plan_of, 'launch:\n- node: {pkg: demo_nodes}\n')
    assert message.endswith("test.launch.yaml:2: node: missing required attribute 'exec'")
    assert "missing required attribute 'cmd'" in error_of(plan_of, 'launch:\n- executable: {name: x}\n')
    assert "missing required attribute 'period'" in error_of(plan_of, 'launch:\n- timer: {children: []}\n')


def test_error_include_cycle(write):
    first = write('a.launch.yaml', 'launch:\n- include: {file: b.launch.yaml}\n')
    write('b.launch.yaml', 'launch:\n- log: {message: x}\n- include: {file: $(dirname)/a.launch.yaml}\n')
    message = error_of(resolve, str(first))
    assert_located(message, 'b.launch.yaml', 3, 'include', 'file')
    chain = message.split('include cycle: ', 1)[1].split(' -> ')
    assert [Path(p).name for p in chain] == ['a.launch.yaml', 'b.launch.yaml', 'a.launch.yaml']
    self_include = write('self.launch.yaml', 'launch:\n- include: {file: self.launch.yaml}\n')
    assert 'include cycle' in error_of(resolve, str(self_include))


def test_error_missing_include_file(plan_of):
    message = error_of(plan_of, 'launch:\n- include: {file: nothere.launch.yaml}\n')
    assert_located(message, 'test.launch.yaml', 2, 'include', 'file')
    assert "no such launch file '" in message and message.endswith("nothere.launch.yaml'")


def test_error_missing_launch_file(tmp_path):
    assert 'no such launch file' in error_of(resolve, str(tmp_path / 'none.launch.yaml'))


def test_error_unknown_launch_argument(plan_of):
    message = error_of(plan_of, 'launch:\n- arg: {name: topic, default: x}\n- arg: {name: rate, default: 1}\n',
                       tpoic='news')
    assert message.endswith("test.launch.yaml: unknown launch argument 'tpoic' (declared arguments: rate, topic)")


def test_error_missing_required_argument_lists_declared(plan_of):
    message = error_of(plan_of, 'launch:\n- arg: {name: robot}\n- arg: {name: rate, default: 1}\n'
                                '- log: {message: $(var robot)}\n')
    assert_located(message, 'test.launch.yaml', 2, 'arg', 'name')
    assert "Required launch argument 'robot' was not given" in message
    assert 'declared arguments: rate, robot' in message


def test_error_required_argument_of_included_file(plan_of, write):
    """As launch: the include must pass an included file's required argument itself; the error
    is the include's, and a configuration set elsewhere does not count."""
    write('inner.launch.yaml', 'launch:\n- arg: {name: who, description: the name}\n')
    message = error_of(plan_of, 'launch:\n- let: {name: who, value: x}\n- include: {file: inner.launch.yaml}\n')
    assert_located(message, 'test.launch.yaml', 3, 'include')
    assert "missing required argument 'who' (description: 'the name'), given: []" in message
    plan_of('launch:\n- include: {file: inner.launch.yaml, arg: [{name: who, value: x}]}\n')


def test_error_if_and_unless_together(plan_of):
    message = error_of(plan_of, "launch:\n- log:\n    message: x\n    if: 'true'\n    unless: 'false'\n")
    assert_located(message, 'test.launch.yaml', 5, 'log', 'unless')


def test_error_bad_choice(plan_of):
    message = error_of(plan_of, 'launch:\n- arg: {name: m, default: a, choice: [{value: a}, {value: b}]}\n', m='c')
    assert message.endswith("test.launch.yaml:2: arg: choice: launch argument 'm' is 'c', not one of: a, b")


def test_error_unknown_package_and_executable(plan_of):
    message = error_of(plan_of, 'launch:\n- node: {pkg: demo_nodes, exec: talker}\n- node: {pkg: nope_pkg, exec: x}\n')
    assert_located(message, 'test.launch.yaml', 3, 'node', 'pkg')
    assert "package 'nope_pkg' not found (packages: " in message
    message = error_of(plan_of, 'launch:\n- node:\n    pkg: demo_nodes\n    exec: talkr\n')
    assert_located(message, 'test.launch.yaml', 4, 'node', 'exec')
    assert message.endswith("no executable 'talkr' in package 'demo_nodes'. Did you mean 'talker'?")
    message = error_of(plan_of, 'launch:\n- node: {pkg: demo_nodes, exec: zzz_nothing_close}\n')
    assert "no executable 'zzz_nothing_close' in package 'demo_nodes' (executables: " in message
    message = error_of(plan_of, 'launch:\n- node: {pkg: turtlesm, exec: turtlesim_node}\n')
    assert message.endswith("package 'turtlesm' not found. Did you mean 'turtlesim'?")
    missing = error_of(plan_of, "launch:\n- executable: {cmd: 'no-such-program-zz --x'}\n")
    assert_located(missing, 'test.launch.yaml', 2, 'executable', 'cmd')
    assert "executable 'no-such-program-zz' not found on PATH" in missing


def test_error_substitution_problems_are_located(plan_of):
    message = error_of(plan_of, 'launch:\n- log:\n    message: "$(var nope)"\n')
    assert_located(message, 'test.launch.yaml', 3, 'log', 'message')
    syntax = error_of(plan_of, 'launch:\n- log: {message: "$(bogus x)"}\n')
    assert_located(syntax, 'test.launch.yaml', 2, 'log', 'message')
    assert "unknown substitution 'bogus'" in syntax
    condition = error_of(plan_of, "launch:\n- log: {message: x, if: 'perhaps'}\n")
    assert_located(condition, 'test.launch.yaml', 2, 'log', 'if')


def test_error_bad_names_and_params(plan_of):
    name = error_of(plan_of, "launch:\n- node: {pkg: demo_nodes, exec: talker, name: 'bad-name'}\n")
    assert_located(name, 'test.launch.yaml', 2, 'node', 'name')
    namespace = error_of(plan_of, "launch:\n- node: {pkg: demo_nodes, exec: talker, namespace: '1robot'}\n")
    assert_located(namespace, 'test.launch.yaml', 2, 'node', 'namespace')
    param_file = error_of(plan_of, 'launch:\n- node:\n    pkg: demo_nodes\n    exec: talker\n    param:\n'
                                   '    - {from: /no/such/params.yaml}\n')
    assert_located(param_file, 'test.launch.yaml', 6, 'param', 'from')
    both = error_of(plan_of, 'launch:\n- node:\n    pkg: demo_nodes\n    exec: talker\n    param:\n'
                             '    - {name: a, value: 1, param: [{name: b, value: 2}]}\n')
    assert "'value' and nested 'param' cannot be used together" in both
    mapping = error_of(plan_of, 'launch:\n- set_parameter: {name: a, value: {b: 1}}\n')
    assert_located(mapping, 'test.launch.yaml', 2, 'set_parameter', 'value')


def test_print_describes_without_side_effects(plan_of, tmp_path):
    plan = plan_of('''
        launch:
        - set_env: {name: ZZ_PRINT, value: shown}
        - node:
            pkg: demo_nodes
            exec: param_talker
            name: pt
            param: [{name: published_text, value: hi}]
        ''')
    text = plan.describe()
    assert 'process [param_talker-1]' in text and 'node: /pt' in text
    assert '--params-file ' + str(tmp_path / 'log' / 'params' / 'param_talker-1.yaml') in text
    assert 'ZZ_PRINT=shown' in text and 'published_text: hi' in text
    assert not (tmp_path / 'log').exists()
