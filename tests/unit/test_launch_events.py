"""launch's event system on zros's launch context, without running anything: events and their
names, EventHandler's matching, locals and handle_once, the per-handler modules with their
targets and results, RegisterEventHandler of a generic handler, and the import hook that must
not mistake a bare `launch/` folder of test files for the launch library."""
from __future__ import annotations

import asyncio
import sys
from pathlib import Path

import pytest

from zros import import_hook
from zros.launch import Event, EventHandler, LaunchContext, LaunchDescription, LaunchDescriptionEntity
from zros.launch.actions import ExecuteProcess, LogInfo, OpaqueFunction, RegisterEventHandler
from zros.launch.description import resolve_actions
from zros.launch.errors import LaunchFileError
from zros.launch.event_handlers import (OnExecutionComplete, OnIncludeLaunchDescription, OnProcessExit, OnProcessIO,
                                        OnProcessStart, OnShutdown)
from zros.launch.events import ExecutionComplete, IncludeLaunchDescription, Shutdown
from zros.launch.events.process import ProcessExited, ProcessIO, ProcessStarted
from zros.launch.plan import EventHandlerEffect, ProcessSpec

PY = sys.executable


def started(action: object, pid: int = 7) -> ProcessStarted:
    return ProcessStarted(action=action, name='p-1', cmd=['p'], cwd=None, env=None, pid=pid)


def exited(action: object, code: int = 0) -> ProcessExited:
    return ProcessExited(action=action, name='p-1', cmd=['p'], cwd=None, env=None, pid=7, returncode=code)


def test_every_event_names_its_class():
    assert Event().name == 'launch.Event'
    assert Shutdown().name == 'launch.events.Shutdown'
    assert started(None).name == 'launch.events.process.ProcessStarted'
    assert started(None).process_name == 'p-1'
    assert exited(None, 3).returncode == 3
    assert isinstance(Shutdown(), Event) and isinstance(ExecutionComplete(action=None), Event)


def test_a_handler_puts_the_event_in_the_locals_and_returns_its_entities():
    context = LaunchContext()
    log = LogInfo(msg='x')
    handler = EventHandler(matcher=lambda event: isinstance(event, Shutdown), entities=[log])
    event = Shutdown(reason='r')
    assert handler.matches(event) and not handler.matches(Event())
    assert handler.handle(event, context) == [log]
    assert context.locals.event is event


def test_a_handle_once_handler_unregisters_itself_and_a_second_event_is_an_error():
    context = LaunchContext()
    handler = EventHandler(matcher=lambda event: True, handle_once=True)
    context.register_event_handler(handler)
    handler.handle(Event(), context)
    assert handler not in context.event_handlers
    with pytest.raises(ValueError):
        handler.handle(Event(), context)


def test_handlers_are_offered_events_newest_first_unless_appended():
    context = LaunchContext()
    first, second, last = (EventHandler(matcher=bool) for _ in range(3))
    context.register_event_handler(first)
    context.register_event_handler(second)
    context.register_event_handler(last, append=True)
    assert context.event_handlers == [second, first, last]


def test_events_queue_from_any_spelling():
    context = LaunchContext()
    context.emit_event_sync(Event())
    asyncio.run(context.emit_event(Shutdown()))
    assert context._event_queue.qsize() == 2


def test_a_process_handler_aimed_at_an_action_takes_only_its_events():
    node, other = ExecuteProcess(cmd=['a']), ExecuteProcess(cmd=['b'])
    on_exit = OnProcessExit(target_action=node, on_exit=[LogInfo(msg='bye')])
    assert on_exit.matches(exited(node)) and not on_exit.matches(exited(other))
    assert not on_exit.matches(started(node))
    anyone = OnProcessStart(on_start=lambda event, context: None)
    assert anyone.matches(started(other))
    picky = OnProcessExit(target_action=lambda action: action is other, on_exit=[])
    assert picky.matches(exited(other)) and not picky.matches(exited(node))


def test_a_handler_function_gets_the_event_and_the_context_and_a_list_stays_a_list():
    seen = []
    context = LaunchContext()
    handler = OnProcessExit(on_exit=lambda event, ctx: seen.append((event.returncode, ctx)))
    handler.handle(exited(None, 2), context)
    assert seen == [(2, context)]
    log = LogInfo(msg='x')
    assert OnProcessStart(on_start=log).handle(started(None), context) == [log]
    assert OnShutdown(on_shutdown=log).handle(Shutdown(), context) is log   # as given, as launch


@pytest.mark.parametrize('make', [
    lambda: OnProcessExit(target_action='not an action', on_exit=[]),
    lambda: OnExecutionComplete(target_action=LogInfo(msg='m'), on_completion='neither actions nor a function'),
    lambda: OnProcessIO(on_stdout='not a function'),
    lambda: RegisterEventHandler('not a handler'),
])
def test_wrong_kinds_are_type_errors_that_name_the_key(make):
    with pytest.raises(TypeError) as raised:
        make()
    assert isinstance(raised.value, LaunchFileError)
    assert ':' in str(raised.value)


def test_process_io_goes_to_the_function_of_its_stream():
    got = []
    handler = OnProcessIO(on_stdout=lambda event: got.append(('out', event.text)),
                          on_stderr=lambda event: got.append(('err', event.text)))
    io = ProcessIO(action=None, name='p-1', cmd=['p'], cwd=None, env=None, pid=1, text=b'hi\n', fd=2)
    assert handler.matches(io) and not handler.matches(started(None))
    handler.handle(io, LaunchContext())
    assert got == [('err', b'hi\n')]


def test_execution_complete_and_include_handlers():
    action = LogInfo(msg='m')
    handler = OnExecutionComplete(target_action=action, on_completion=[])
    assert handler.matches(ExecutionComplete(action=action))
    assert not handler.matches(ExecutionComplete(action=LogInfo(msg='n')))
    description = LaunchDescription([])
    include = IncludeLaunchDescription(description)
    assert OnIncludeLaunchDescription().handle(include, LaunchContext()) is description


def test_actions_and_descriptions_are_launch_description_entities():
    assert isinstance(LogInfo(msg='m'), LaunchDescriptionEntity)
    assert isinstance(LaunchDescription([]), LaunchDescriptionEntity)


def test_register_event_handler_of_a_generic_handler_registers_it_on_the_resolving_context(tmp_path: Path):
    handler = EventHandler(matcher=lambda event: False, entities=[OpaqueFunction(function=lambda context: None)])
    plan = resolve_actions([RegisterEventHandler(handler)], str(tmp_path / 'x.launch.py'))
    assert handler in plan.context.event_handlers
    assert not [effect for effect in plan.effects if isinstance(effect, EventHandlerEffect)]


def test_the_supervisor_asks_a_function_target_which_processes_it_watches():
    node, other = ExecuteProcess(cmd=['a']), ExecuteProcess(cmd=['b'])
    effect = EventHandlerEffect('exit', lambda action: action is node, [])
    assert effect.matches(ProcessSpec('a', ('a',), source=node))
    assert not effect.matches(ProcessSpec('b', ('b',), source=other))


def test_a_bare_folder_named_launch_does_not_hide_zros_launch(tmp_path: Path, monkeypatch: pytest.MonkeyPatch):
    (tmp_path / 'launch').mkdir()    # launch's own test tree has one: test files, no __init__.py
    monkeypatch.syspath_prepend(str(tmp_path))
    finder = import_hook.RosModuleFinder()
    monkeypatch.delitem(sys.modules, 'launch', raising=False)
    assert not finder._installed('launch')
    assert import_hook.module_target('launch', finder._installed) == 'zros.launch'


def test_locals_are_read_only_and_a_pushed_layer_hides_then_goes():
    context = LaunchContext()
    context.extend_locals({'event': 1})
    with pytest.raises(AttributeError):
        context.locals.event = 2
    context._push_locals()
    context.extend_locals({'event': 2, 'extra': 3})
    assert (context.locals.event, context.locals.extra) == (2, 3)
    context._pop_locals()
    assert context.get_locals_as_dict() == {'event': 1}
    with pytest.raises(AttributeError):
        context.locals.extra
    with pytest.raises(RuntimeError):
        context._pop_locals()


def test_execution_complete_is_queued_only_when_a_handler_would_take_it(tmp_path: Path):
    quiet, watched = LogInfo(msg='a'), LogInfo(msg='b')
    plan = resolve_actions([RegisterEventHandler(OnExecutionComplete(target_action=watched, on_completion=[])),
                            quiet, watched], str(tmp_path / 'x.launch.py'))
    queued = [plan.context._event_queue.get_nowait() for _ in range(plan.context._event_queue.qsize())]
    assert [event.action for event in queued] == [watched]


def test_unregister_event_handler_takes_a_queue_handler_off_once():
    from zros.launch import EventHandler, LaunchContext
    from zros.launch.actions import RegisterEventHandler, UnregisterEventHandler
    context = LaunchContext()
    handler = EventHandler(matcher=lambda event: True)
    RegisterEventHandler(handler).execute(context)
    assert handler in context.event_handlers
    UnregisterEventHandler(handler).execute(context)
    assert handler not in context.event_handlers
    with pytest.raises(ValueError):
        UnregisterEventHandler(handler).execute(context)


def test_register_event_handler_describes_its_actions_as_conditional():
    from zros.launch import EventHandler
    from zros.launch.actions import LogInfo, RegisterEventHandler
    action = LogInfo(msg='later')
    register = RegisterEventHandler(EventHandler(matcher=lambda event: True, entities=[action]))
    assert register.describe_sub_entities() == []
    [(_, entities)] = register.describe_conditional_sub_entities()
    assert entities == [action]


def test_context_has_the_run_async_loop_only_while_it_runs():
    import asyncio
    from zros.launch import LaunchContext, LaunchDescription, LaunchService
    from zros.launch.actions import OpaqueFunction
    assert LaunchContext().asyncio_loop is None
    seen = []
    service = LaunchService()
    service.include_launch_description(LaunchDescription([
        OpaqueFunction(function=lambda context: seen.append(context.asyncio_loop))]))
    loop = asyncio.new_event_loop()
    try:
        assert loop.run_until_complete(service.run_async()) == 0   # no process: idle at once
    finally:
        loop.close()
    assert seen == [loop] and service.context.asyncio_loop is None


def test_an_opaque_function_under_a_shutdown_handler_runs_at_shutdown_not_while_planning(tmp_path: Path):
    # Nav2 Jazzy's tb3_simulation_launch.py removes its temporary world file this way.
    calls = []
    remove = OpaqueFunction(function=lambda context: calls.append('removed'))
    plan = resolve_actions([RegisterEventHandler(OnShutdown(on_shutdown=[remove]))], str(tmp_path / 'x.launch.py'))
    assert calls == []
    (effect,) = [e for e in plan.effects if isinstance(e, EventHandlerEffect)]
    assert effect.event == 'shutdown' and effect.deferred is not None
    effect.effects_at_shutdown('done')
    assert calls == ['removed']
