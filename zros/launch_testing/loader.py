"""A launch test module, as launch_testing reads one: `generate_test_description()` (returning
a LaunchDescription, or `(LaunchDescription, {name: value})`), the unittest.TestCase classes
that run while the launch is up, and those marked `@post_shutdown_test()` that run after it.

Tests receive what they name: `proc_output`, `proc_info`, `launch_service`, `test_args` and the
names of the dict returned with the description, as arguments of test methods, setUp/tearDown
and setUpClass/tearDownClass, and as attributes (`self.proc_output`).
"""
from __future__ import annotations

import functools
import hashlib
import importlib.util
import inspect
import os
import sys
import unittest
from types import ModuleType
from typing import Any, Callable, Iterator

from zros.launch.errors import LaunchError
from zros.launch.files import python_error, read_text
from zros.launch.launch_description import LaunchDescription
from zros.launch_testing.actions import ReadyToTest
from zros.launch_testing.decorator import DEFAULT_READY_TIMEOUT

__all__ = ['LaunchTest', 'LaunchTestError', 'ATTRIBUTES']

#: What every test class also gets as an attribute (`self.proc_output`), as in launch_testing.
ATTRIBUTES = ('proc_output', 'proc_info', 'launch_service', 'test_args')


class LaunchTestError(LaunchError):
    """A launch test file that cannot run (one line naming the file)."""


def _walk(entities: list) -> Iterator[Any]:
    for entity in entities:
        yield entity
        yield from _walk(entity.describe_sub_entities())
        for _, entities in entity.describe_conditional_sub_entities():
            yield from _walk(entities)


class LaunchTest:
    """One launch test module.

    Args:
        module: the imported test module (under the import hook: `import launch_testing` is
            zros.launch_testing).
        path: its file, for error messages.

    Raises:
        LaunchTestError: no generate_test_description(), or one taking arguments zros does
            not give.
    """

    def __init__(self, module: ModuleType, path: str) -> None:
        self.path = path
        self.name = module.__name__
        generate = getattr(module, 'generate_test_description', None)
        if not callable(generate):
            raise LaunchTestError(f'{path}: no generate_test_description() function (a launch test defines one '
                                  'returning a LaunchDescription with launch_testing.actions.ReadyToTest())')
        parameters = inspect.signature(generate).parameters
        extra = [name for name in parameters if name != 'ready_fn']
        if extra:
            raise LaunchTestError(f"{path}: generate_test_description() takes '{extra[0]}', which zros does not "
                                  'give (only the old-style ready_fn; launch_testing.parametrize is not supported)')
        self._generate = generate
        self.takes_ready_fn = 'ready_fn' in parameters
        self.keep_alive = bool(getattr(generate, '__markers__', {}).get('keep_alive'))
        self.ready_timeout = float(getattr(generate, '__ready_to_test_action_timeout__', DEFAULT_READY_TIMEOUT))
        self.active_tests = _load_tests(module, post_shutdown=False)
        self.post_shutdown_tests = _load_tests(module, post_shutdown=True)

    @classmethod
    def from_file(cls, path: str) -> 'LaunchTest':
        """Import a launch test file under the import hook (what `zros test` runs)."""
        from zros.import_hook import install
        install()
        text = read_text(path, 'launch test file')
        name = os.path.splitext(os.path.basename(path))[0]
        if name in sys.modules:   # a test named like a module that is already loaded (`test`)
            name += '_' + hashlib.sha1(os.path.abspath(path).encode()).hexdigest()[:8]
        spec = importlib.util.spec_from_file_location(name, path)
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module   # unittest and dataclasses look classes' modules up
        try:
            exec(compile(text, path, 'exec'), module.__dict__)  # noqa: S102 - running the test file is the point
        except SyntaxError as exc:
            raise LaunchTestError(f'{path}:{exc.lineno or 1}: invalid Python: {exc.msg}') from None
        except Exception as exc:  # noqa: BLE001 - whatever the file raises is one line
            raise python_error(path, exc) from None
        return cls(module, path)

    def describe(self, ready: Callable[[], None]) -> tuple[LaunchDescription, dict]:
        """Call generate_test_description(); `ready` is called when the launch reaches its
        ReadyToTest (or when an old-style test calls its `ready_fn`)."""
        try:
            result = self._generate(ready_fn=ready) if self.takes_ready_fn else self._generate()
        except LaunchError:
            raise
        except Exception as exc:  # noqa: BLE001 - the user's function: one line
            raise python_error(self.path, exc) from None
        description, values = result if isinstance(result, tuple) and len(result) == 2 else (result, {})
        if not isinstance(description, LaunchDescription) or not isinstance(values, dict):
            raise LaunchTestError(f'{self.path}: generate_test_description() returned {type(result).__name__}, not a '
                                  'LaunchDescription or (LaunchDescription, dict)')
        readies = [entity for entity in _walk(description.entities) if isinstance(entity, ReadyToTest)]
        if not readies and not self.takes_ready_fn:
            raise LaunchTestError(f'{self.path}: generate_test_description() returned a LaunchDescription without '
                                  'launch_testing.actions.ReadyToTest() (the tests start when the launch reaches it)')
        for action in readies:
            action._add_callback(ready)
        return description, values

    @staticmethod
    def bind(suite: unittest.TestSuite, values: dict[str, Any]) -> None:
        """Give the tests of `suite` what they ask for by argument name, and ATTRIBUTES as attributes."""
        classes = []
        for test in _tests(suite):
            for name in (test._testMethodName, 'setUp', 'tearDown'):
                setattr(test, name, _bind(getattr(test, name), values))
            if type(test) not in classes:
                classes.append(type(test))
        for test_class in classes:
            for name in ATTRIBUTES:
                if name in values:
                    setattr(test_class, name, values[name])
            for name in ('setUpClass', 'tearDownClass'):
                setattr(test_class, name, _bind(getattr(test_class, name), values))


def _bind(function: Callable, values: dict[str, Any]) -> Callable:
    wanted = inspect.signature(function).parameters
    return functools.partial(function, **{name: value for name, value in values.items() if name in wanted})


def _tests(suite: Any) -> Iterator[unittest.TestCase]:
    if isinstance(suite, unittest.TestCase):
        yield suite
    else:
        for item in suite:
            yield from _tests(item)


def _load_tests(module: ModuleType, *, post_shutdown: bool) -> unittest.TestSuite:
    """The module's TestCase classes of one kind, each loaded from a subclass of its own, so
    binding values never changes the user's class."""
    loader = unittest.TestLoader()
    suite = unittest.TestSuite()
    for value in vars(module).values():
        if (isinstance(value, type) and issubclass(value, unittest.TestCase)
                and bool(getattr(value, '__post_shutdown_test__', False)) == post_shutdown):
            isolated = type(value.__name__, (value,), {'__module__': value.__module__, '__qualname__': value.__qualname__})
            suite.addTests(loader.loadTestsFromTestCase(isolated))
    return suite
