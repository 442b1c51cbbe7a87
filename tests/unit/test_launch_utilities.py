"""zros.launch.utilities (launch.utilities): argument checks, substitution lists and the typed
values launch actions coerce, in the cases launch code relies on."""
from __future__ import annotations

from typing import List

import pytest

from zros.launch.context import LaunchContext
from zros.launch.substitutions import LaunchConfiguration, TextSubstitution
from zros.launch.template import Substitution
from zros.launch.utilities import (ensure_argument_type, is_a, is_a_subclass, normalize_to_list_of_substitutions,
                                   perform_substitutions)
from zros.launch.utilities.type_utils import (coerce_list, coerce_to_type, extract_type, get_typed_value,
                                              is_instance_of, is_substitution, normalize_typed_substitution,
                                              perform_typed_substitution)


# -- argument checks ----------------------------------------------------------------------------
def test_a_wrong_argument_type_names_the_argument_and_the_caller():
    ensure_argument_type(True, [str, int], 'flag')  # a bool is an int
    with pytest.raises(TypeError, match=r"'MyAction': expected 'period' to be one of \[float, int\]"):
        ensure_argument_type('1', (float, int), 'period', 'MyAction')
    with pytest.raises(TypeError):
        ensure_argument_type(1, None, 'x')  # types must be a class or classes


def test_is_a_subclass_takes_instances_and_classes():
    class Base:
        pass

    class Derived(Base):
        pass

    assert is_a(Derived(), Base) and not is_a(Derived, Base)
    assert is_a_subclass(Derived, Base) and is_a_subclass(Derived(), Base)
    assert not is_a_subclass(Base, Derived) and not is_a_subclass('text', Base)
    with pytest.raises(RuntimeError):
        is_a(1, 'int')


# -- substitution lists -------------------------------------------------------------------------
def test_strings_become_text_substitutions_and_numbers_are_refused():
    subs = normalize_to_list_of_substitutions(['a', LaunchConfiguration('x'), ''])
    assert [type(s) for s in subs] == [TextSubstitution, LaunchConfiguration, TextSubstitution]
    assert normalize_to_list_of_substitutions(()) == []
    for bad in (None, 2, ['a', ['b']], [1.5]):
        with pytest.raises(TypeError):
            normalize_to_list_of_substitutions(bad)


def test_perform_substitutions_concatenates_in_the_launch_context():
    context = LaunchContext(launch_arguments={'robot': 'r1'})
    subs = normalize_to_list_of_substitutions(['/', LaunchConfiguration('robot'), '/scan'])
    assert perform_substitutions(context, subs) == '/r1/scan'
    with pytest.raises(AttributeError):
        perform_substitutions(context, ['plain text is not a substitution'])
    with pytest.raises(NotImplementedError):
        perform_substitutions(context, [Substitution()])


# -- typed values -------------------------------------------------------------------------------
@pytest.mark.parametrize('text, data_type, expected', [
    ('3', None, 3), ('3.', None, 3.0), ('yes', None, True), ("'3'", None, '3'), ('', None, ''),
    ('[1, 2]', None, [1, 2]), ('3', float, 3.0), ('3', str, '3'), ('on', bool, True), ('0', bool, False),
    ('[a, b]', List[str], ['a', 'b']), ('x', int, ValueError), ('3.5', int, ValueError), ('', bool, ValueError),
    ('[1, 2.5]', None, ValueError), ('{a: 1}', None, ValueError), ('[1]', int, ValueError),
])
def test_text_coerces_by_yaml_and_the_requested_type(text, data_type, expected):
    if expected is ValueError:
        with pytest.raises(ValueError):
            coerce_to_type(text, data_type)
    else:
        result = coerce_to_type(text, data_type)
        assert result == expected and type(result) is type(expected)


def test_can_be_str_keeps_what_does_not_coerce():
    assert coerce_to_type('$(var x)', int, can_be_str=True) == '$(var x)'
    assert coerce_list(['a', '2'], int, can_be_str=True) == ['a', 2]
    with pytest.raises(ValueError):
        coerce_list(['a', '2'], int)


def test_get_typed_value_refuses_a_list_for_a_scalar_type():
    assert get_typed_value(['1', '2'], List[int]) == [1, 2]
    with pytest.raises(TypeError):
        get_typed_value(['1', '2'], int)
    with pytest.raises(TypeError):
        coerce_to_type(3, int)


def test_type_checks_know_only_launchs_types():
    assert extract_type(List[bool]) == (bool, True)
    assert is_instance_of(['1', 2], List[int], can_be_str=True)
    assert not is_instance_of(1, float) and not is_instance_of([1], int)
    for bad in (bytes, list, List, dict):
        with pytest.raises(ValueError):
            extract_type(bad)


def test_a_list_of_strings_and_substitutions_is_one_substitution():
    assert is_substitution(['/ns/', TextSubstitution(text='x')])
    assert not is_substitution(['a', 'b']) and not is_substitution('a') and not is_substitution([])
    joined = normalize_typed_substitution(['1', TextSubstitution(text='0')], int)
    assert perform_typed_substitution(LaunchContext(), joined, int) == 10


def test_a_list_value_holds_values_and_substitution_items():
    context = LaunchContext(launch_arguments={'b': '2'})
    value = normalize_typed_substitution([1, [LaunchConfiguration('b')], 3.5], List[float])
    assert value[0] == 1.0 and type(value[0]) is float
    assert perform_typed_substitution(context, value, List[float]) == [1.0, 2.0, 3.5]
    with pytest.raises(TypeError):
        normalize_typed_substitution([1, 'a'], List[int])   # mixed plain items
    with pytest.raises(TypeError):
        normalize_typed_substitution([1, 2], int)           # a list for a scalar
    with pytest.raises(ValueError):
        perform_typed_substitution(context, [[TextSubstitution(text='x')]], List[int])


def test_zros_launch_types_attributes_by_the_same_rules():
    """A typed attribute (respawn, respawn_delay ...) converts its text through coerce_to_type,
    so a launch file gets launch's YAML spellings and launch's errors alike."""
    from zros.launch.errors import LaunchFileError, Origin
    from zros.launch.template import Typed
    origin = Origin('f.launch.py', 3, 'Node', 'respawn')
    context = LaunchContext(launch_arguments={'delay': '2'})
    assert Typed.of('on', bool, origin).perform(context) is True
    assert Typed.of(' 1 ', bool, origin).perform(context) is True
    assert Typed.of(LaunchConfiguration('delay'), float, origin).perform(context) == 2.0
    assert Typed.of(3, float, origin).perform(context) == 3.0
    with pytest.raises(LaunchFileError, match=r"^f\.launch\.py:3: Node: respawn: expected an int, got string '1\.'$"):
        Typed.of('1.', int, origin)


# -- signals --------------------------------------------------------------------------------------
@pytest.fixture
def quiet_sigusr():
    """SIGUSR1/2 with a no-op Python handler (their default ends the process), restored after."""
    import signal
    previous = {s: signal.signal(s, lambda *_: None) for s in (signal.SIGUSR1, signal.SIGUSR2)}
    yield
    for s, handler in previous.items():
        signal.signal(s, handler)


def test_signals_reach_the_loop_only_inside_the_managers_context(quiet_sigusr):
    import asyncio
    import signal

    from zros.launch.utilities import AsyncSafeSignalManager
    loop = asyncio.new_event_loop()
    try:
        outer, inner = AsyncSafeSignalManager(loop), AsyncSafeSignalManager(loop)
        seen: list[tuple[str, int]] = []
        outer.handle(signal.SIGUSR1, lambda s: seen.append(('outer', s)))
        inner.handle(signal.SIGUSR1, lambda s: seen.append(('inner', s)))

        def deliver(signum):
            loop.call_soon(signal.raise_signal, signum)
            loop.run_until_complete(asyncio.sleep(0.2))

        with outer:
            with inner:      # nested: the inner one passes the signal on to the outer one
                deliver(signal.SIGUSR1)
            assert seen == [('inner', signal.SIGUSR1), ('outer', signal.SIGUSR1)]
            assert outer.handle(signal.SIGUSR1, None) is not None
            deliver(signal.SIGUSR1)
            assert len(seen) == 2
        outer.handle(signal.SIGUSR2, lambda s: seen.append(('late', s)))
        deliver(signal.SIGUSR2)              # outside the context: not handled
        assert len(seen) == 2
        assert signal.set_wakeup_fd is AsyncSafeSignalManager._set_wakeup_fd   # restored
    finally:
        loop.close()


# -- entity walks ---------------------------------------------------------------------------------
def test_entities_are_visited_depth_first_collecting_their_futures():
    import asyncio

    from zros.launch import LaunchDescription
    from zros.launch.actions import LogInfo
    from zros.launch.utilities import normalize_to_list_of_entities, visit_all_entities_and_collect_futures
    loop = asyncio.new_event_loop()

    class Waiting:
        """An entity that waits on a future and has `children` sub-entities."""

        def __init__(self, name, children=()):
            self.name, self.children, self.future = name, list(children), loop.create_future()

        def visit(self, context):
            return self.children or None

        def get_asyncio_future(self):
            return self.future

    try:
        tree = Waiting('a', [Waiting('b', [Waiting('c')]), LogInfo(msg='no future'), Waiting('d')])
        found = visit_all_entities_and_collect_futures(tree, LaunchContext())
        assert [entity.name for entity, _ in found] == ['a', 'b', 'c', 'd']
        assert all(future is entity.future for entity, future in found)
        log = LogInfo(msg='x')
        assert normalize_to_list_of_entities([log, [tree], LaunchDescription([])])[:2] == [log, tree]
    finally:
        loop.close()
