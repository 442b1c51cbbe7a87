"""launch's Python substitution and condition objects used on their own (`Sub(...).perform(ctx)`
on a bare LaunchContext), as launch files and OpaqueFunctions use them; the `$(...)` text forms
are in test_launch_parse.py."""
from __future__ import annotations

import os
import warnings

import pytest

from zros.launch import LaunchContext
from zros.launch.conditions import (Condition, IfCondition, InvalidConditionExpressionError, LaunchConfigurationEquals,
                                    UnlessCondition, evaluate_condition_expression)
from zros.launch.errors import LaunchError
from zros.launch.frontend.parse_substitution import parse_substitution
from zros.launch.substitutions import (EqualsSubstitution, IfElseSubstitution, LaunchLogDir, NotEqualsSubstitution,
                                       PythonExpression, SubstitutionFailure, TextSubstitution, ThisLaunchFile,
                                       ThisLaunchFileDir)
from zros.launch.substitutions.launch_configuration import LaunchConfiguration as ConfigurationByModule
from zros.launch.substitutions.substitution_failure import SubstitutionFailure as FailureByModule


def test_launch_module_paths_give_the_one_class():
    from zros.launch.substitutions import LaunchConfiguration
    assert FailureByModule is SubstitutionFailure
    assert ConfigurationByModule is LaunchConfiguration


def test_python_expression_scope_is_the_modules_it_lists():
    context = LaunchContext()
    assert PythonExpression('ceil(1.5) + math.floor(1.5)').perform(context) == '3'
    assert PythonExpression(['sys.maxsize > ', '0'], ['sys']).perform(context) == 'True'
    with pytest.raises(NameError):
        PythonExpression('math.pi', []).perform(context)
    with pytest.raises(SubstitutionFailure):   # the same error, as the launch sees it
        PythonExpression('floor(1.5)', ['sys']).perform(context)


def test_python_expression_describes_itself_as_launch_does():
    assert PythonExpression('ceil(x)').describe() == "PythonExpr('ceil(x)', ['math'])"
    assert PythonExpression(['a', ' + 1'], ['sys', 'math']).describe() == "PythonExpr('a' + ' + 1', ['sys', 'math'])"
    assert PythonExpression('1', []).describe() == "PythonExpr('1', [])"
    parsed, = parse_substitution('$(eval "1" " math,sys ")')
    assert [module.text for module in parsed.python_modules] == ['math', 'sys']


@pytest.mark.parametrize(('left', 'right', 'equal'), [
    (None, '', True), (True, '1', True), ('False', 0, True), (True, '10', False),
    (10, 10 + 1e-10, True), ('nan', 'nan', False), (float('inf'), 'inf', True), ('wow', 1, False),
])
def test_equals_compares_as_bools_then_numbers_then_text(left, right, equal):
    context = LaunchContext()
    assert EqualsSubstitution(left, right).perform(context) == str(equal).lower()
    assert NotEqualsSubstitution(right, left).perform(context) == str(not equal).lower()


def test_if_else_reads_a_typed_bool_and_needs_a_value():
    context = LaunchContext()
    assert IfElseSubstitution('on', 'yes', 'no').perform(context) == 'yes'
    assert IfElseSubstitution('No', else_value='else').perform(context) == 'else'
    with pytest.raises(SubstitutionFailure):
        IfElseSubstitution('maybe', 'a').perform(context)
    with pytest.raises(LaunchError):
        IfElseSubstitution('true')


def test_this_launch_file_outside_a_file_is_the_local_or_an_error():
    context = LaunchContext()
    for substitution in (ThisLaunchFile(), ThisLaunchFileDir()):
        with pytest.raises(SubstitutionFailure, match='no current launch file'):
            substitution.perform(context)
    context.extend_locals({'current_launch_file_path': 'a/b.py', 'current_launch_file_directory': 'a'})
    assert (ThisLaunchFile().perform(context), ThisLaunchFileDir().perform(context)) == ('a/b.py', 'a')


def test_log_dir_of_a_hand_made_context_is_made_once(tmp_path, monkeypatch):
    monkeypatch.setenv('ZROS_LOG_DIR', str(tmp_path))
    context = LaunchContext()
    first = LaunchLogDir().perform(context)
    assert os.path.isdir(first) and os.path.dirname(first) == str(tmp_path)
    assert parse_substitution('$(launch_log_dir)')[0].perform(context) == first
    assert isinstance(parse_substitution('$(launch_log_dir)')[0], LaunchLogDir)


def test_conditions_read_true_false_one_zero_only():
    context = LaunchContext()
    assert evaluate_condition_expression(context, [TextSubstitution(text=' TRUE ')]) is True
    assert UnlessCondition('0').evaluate(context) is True
    for bad in ('', 'yes'):
        with pytest.raises(InvalidConditionExpressionError):
            IfCondition(bad).evaluate(context)
    assert Condition().evaluate(context) is False


def test_launch_configuration_equals_is_deprecated_but_works():
    context = LaunchContext(launch_arguments={'mode': 'fast'})
    with pytest.warns(UserWarning, match='deprecated'):
        condition = LaunchConfigurationEquals('mode', 'fast')
    with warnings.catch_warnings():
        warnings.simplefilter('error')
        assert condition.evaluate(context) is True
    assert 'mode' in context.read_configurations
