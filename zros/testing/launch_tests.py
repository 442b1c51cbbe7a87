"""launch_testing files under pytest, as `colcon test` runs them: every test module that
defines `generate_test_description()` becomes one pytest item that runs its launch and its
tests (zros.launch_testing.runner). The module is imported under the import hook, so it stays
as ROS wrote it (`import launch_testing`, `from launch import LaunchDescription`).

Modules are told apart by their source (a top-level `def generate_test_description`, found by
parsing, not importing): other test modules are collected by pytest as always.
"""
from __future__ import annotations

import ast
import sys
import tempfile
from pathlib import Path
from typing import Any, Iterator

import pytest

__all__ = ['is_launch_test', 'make_launch_test_module', 'LaunchTestModule', 'LaunchTestItem', 'LaunchTestFailed']

def is_launch_test(path: Path) -> bool:
    """Whether the module defines generate_test_description() at top level (a module that
    does not parse is left to pytest, which reports it)."""
    try:
        tree = ast.parse(Path(path).read_bytes(), str(path))
    except (OSError, SyntaxError, ValueError):
        return False
    return any(isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and node.name == 'generate_test_description'
               for node in tree.body)


def make_launch_test_module(module_path: Path, parent: Any) -> 'LaunchTestModule | None':
    """The collector for a launch test module; None for any other module."""
    if not is_launch_test(module_path):
        return None
    from zros.import_hook import install
    install()
    return LaunchTestModule.from_parent(parent, path=module_path)


class LaunchTestFailed(Exception):
    """Some of a launch test's tests failed (or its launch did); `outcome` says which."""

    def __init__(self, outcome: Any) -> None:
        super().__init__(f'{len(outcome.failures())} failure(s)')
        self.outcome = outcome


class LaunchTestModule(pytest.Module):
    """A launch test module: imported as pytest imports test modules, collected as one item
    (its TestCase classes need the launch, so pytest must not run them on their own)."""

    def collect(self) -> Iterator[pytest.Item]:
        yield LaunchTestItem.from_parent(self, name=self.obj.__name__)


class LaunchTestItem(pytest.Item):
    """Runs the module's launch, active tests and post-shutdown tests; fails with each failed
    test's traceback, or with one line when the file cannot run."""

    def runtest(self) -> None:
        from zros.launch import parse_launch_arguments
        from zros.launch_testing.loader import LaunchTest
        from zros.launch_testing.runner import run_launch_test
        launch_arguments = parse_launch_arguments(sum(self.config.getoption('launch_args') or [], []))
        test = LaunchTest(self.parent.obj, str(self.path))
        with tempfile.TemporaryDirectory(prefix='zros-launch-test-') as log_dir:
            outcome = run_launch_test(test, log_dir=Path(log_dir), launch_arguments=launch_arguments,
                                      screen=sys.stdout, stream=sys.stdout)
        if not outcome.ok:
            raise LaunchTestFailed(outcome)

    def repr_failure(self, excinfo: pytest.ExceptionInfo[BaseException], style: Any = None) -> Any:
        from zros.launch import LaunchError
        if isinstance(excinfo.value, LaunchTestFailed):
            return '\n\n'.join(f'FAIL: {name}\n{text.rstrip()}' for name, text in excinfo.value.outcome.failures())
        if isinstance(excinfo.value, LaunchError):
            return str(excinfo.value)
        return super().repr_failure(excinfo, style=style)

    def reportinfo(self) -> tuple[Path, int, str]:
        return self.path, 0, f'launch test: {self.name}'
