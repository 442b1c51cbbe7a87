"""The public API as editors and checkers see it: generic message types and docstrings.

Pure and quick: no Zenoh session and no process but mypy itself. The checker reads the
configuration in pyproject.toml ([tool.mypy]); a user program is checked from the repository
root so that `import zros` resolves to this tree. Interface classes are built at run time, so
the programs declare stand-ins with the shape of generated ones.
"""
from __future__ import annotations

import importlib.util
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from conftest import REPO, load_tool

needs_mypy = pytest.mark.skipif(importlib.util.find_spec('mypy') is None,
                                reason='mypy is not installed (pip install -e ".[dev]")')

# Stand-ins for interfaces.std_msgs.msg.String and interfaces.example_interfaces.srv.AddTwoInts.
_STAND_INS = '''
from zros.node import Node
from zros.publisher import Publisher


class String:
    def __init__(self, data: str = '') -> None:
        self.data = data


class AddTwoInts:
    class Request:
        a: int = 0
        b: int = 0

    class Response:
        sum: int = 0
'''

# What a course program does, typed: every line must check.
_WELL_TYPED = _STAND_INS + '''

def build(node: Node) -> None:
    pub = node.create_publisher(String, 'chatter', 10)
    pub.publish(String(data='x'))
    typed: Publisher[String] = pub

    def on_message(msg: String) -> None:
        print(msg.data)
    node.create_subscription(String, 'chatter', on_message, 10)
    node.create_subscription(String, 'chatter', lambda msg, info: print(msg.data, info), 10)

    client = node.create_client(AddTwoInts, 'add_two_ints')
    response: AddTwoInts.Response | None = client.call(AddTwoInts.Request())   # None: timed out (rclpy's hint)
    total: int = response.sum if response is not None else 0
    future = client.call_async(AddTwoInts.Request())
    done: AddTwoInts.Response | None = future.result()
'''

# One mistake per line; the checker must report each of these lines.
_MISTAKES = {
    'pub.publish(42)': 'publish an int on a String publisher',
    "node.create_subscription(String, 'chatter', on_int, 10)": 'a callback that takes an int',
    'client.call(String())': 'a String as a service request',
    'wrong: Publisher[int] = pub': 'a String publisher as a Publisher[int]',
}
_ILL_TYPED = _STAND_INS + '''

def on_int(value: int) -> None:
    print(value)


def build(node: Node) -> None:
    pub = node.create_publisher(String, 'chatter', 10)
    client = node.create_client(AddTwoInts, 'add_two_ints')
''' + ''.join(f'    {line}\n' for line in _MISTAKES)


@pytest.fixture(scope='module')
def mypy_cache(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """One cache for the file's runs: the first analyses zros, the others reuse it."""
    return tmp_path_factory.mktemp('mypy-cache')


def _mypy(cache: Path, program: Path | None = None, source: str = '') -> subprocess.CompletedProcess:
    """Run mypy from the repository root: on `source` written to `program`, or with no program
    on the files pyproject.toml configures."""
    targets = []
    if program is not None:
        program.write_text(source)
        targets.append(str(program))
    return subprocess.run([sys.executable, '-m', 'mypy', '--cache-dir', str(cache), '--no-error-summary',
                           *targets], cwd=REPO, capture_output=True, text=True, timeout=110)


@needs_mypy
def test_public_api_modules_type_check(mypy_cache: Path) -> None:
    result = _mypy(mypy_cache)
    assert result.returncode == 0, result.stdout + result.stderr


@needs_mypy
def test_a_user_program_checks_with_message_types_inferred(mypy_cache: Path, tmp_path: Path) -> None:
    result = _mypy(mypy_cache, tmp_path / 'talker.py', _WELL_TYPED)
    assert result.returncode == 0, result.stdout + result.stderr


@needs_mypy
def test_wrong_message_types_are_reported_where_they_are_written(mypy_cache: Path, tmp_path: Path) -> None:
    program = tmp_path / 'mistakes.py'
    result = _mypy(mypy_cache, program, _ILL_TYPED)
    assert result.returncode == 1, result.stdout + result.stderr
    lines = program.read_text().splitlines()
    reported = {int(line.split(':')[1]) for line in result.stdout.splitlines() if ': error:' in line}
    for mistake, what in _MISTAKES.items():
        number = next(i for i, text in enumerate(lines, 1) if text.strip() == mistake)
        assert number in reported, f'not reported: {what} (line {number})\n{result.stdout}'


# -- tools/docstring_coverage.py ---------------------------------------------------------------

def _coverage_tool():
    return load_tool('docstring_coverage')


def test_coverage_counts_public_names_methods_and_properties_once() -> None:
    import ast
    tool = _coverage_tool()
    source = textwrap.dedent('''
        def documented():
            """Yes."""
        def undocumented(): pass
        def _private(): pass
        class Thing:
            """A class."""
            def __init__(self): pass
            @property
            def size(self):
                """Its size."""
            @size.setter
            def size(self, value): pass
            def bare(self): pass
            def _hidden(self): pass
        class _Private:
            def method(self): pass
    ''')
    names = {n.qualname: n.documented for n in tool.public_names(ast.parse(source))}
    assert names == {'documented': True, 'undocumented': False, 'Thing': True, 'Thing.size': True,
                     'Thing.bare': False}


def test_public_api_modules_are_documented(capsys: pytest.CaptureFixture[str]) -> None:
    tool = _coverage_tool()
    paths = [REPO / module for module in tool.PUBLIC_API_MODULES]
    assert tool.main(paths, fail_under=90.0, show_missing=True) == 0, capsys.readouterr().out


def test_coverage_tool_rejects_a_missing_file_in_one_line() -> None:
    result = subprocess.run([sys.executable, str(REPO / 'tools' / 'docstring_coverage.py'), 'no/such/file.py'],
                            capture_output=True, text=True, timeout=30)
    assert result.returncode == 2
    assert result.stderr.strip() == 'docstring_coverage: no/such/file.py: no such file'
