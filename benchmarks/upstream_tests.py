"""Upstream test suites, run unmodified: how many of the tests that rclpy, launch, launch_ros,
tf2_ros_py and nav2_simple_commander ship pass under `zros python -m pytest`.

    python benchmarks/upstream_tests.py [--interfaces IFACES] SUITE=DIR [SUITE=DIR ...] [--json out.json]

Each DIR is a suite's test folder as fetched at its jazzy commit (nothing is fetched here and
nothing is copied into zros; a checkout or `git archive` keeps the files' modes, which launch's
command tests need to run their scripts), for example
`rclpy=rclpy/rclpy/test launch=launch/launch/test launch_xml=launch/launch_xml/test
launch_yaml=launch/launch_yaml/test launch_ros=launch_ros/test_launch_ros/test
tf2_ros_py=geometry2/tf2_ros_py/test nav2_simple_commander=nav2/nav2_simple_commander/test`.
IFACES is a folder holding ROS interface packages the suites import (by default
benchmarks/upstream_interfaces: `test_msgs`, in rcl_interfaces's shape); it goes on
ZROS_INTERFACE_PATH. Each suite's folder goes on PYTHONPATH, as colcon's
pytest has it (launch's tests import their `temporary_environment` helper so), beside an empty
`test_rclpy` module: rclpy's test package imports that compiled test extension, which tests
rclpy's C internals and has no part in the API. launch's tests import osrf_pycommon, which the
`bench` extra installs (`pip install -e ".[bench]"`).

Each test file runs in a pytest process of its own (a file that hangs or crashes costs only
itself), under a timeout. A test counts once: the tests a file defines are counted from its
source (functions and methods named `test*`, each parametrization once per case where pytest
could collect it), so a file that pytest cannot even import counts all its tests as failed, as
they are for a user. Tests of internals rather than the API (`private_tests`: rclpy's C
binding module, C structs, class-private attributes) are left out and counted apart. The linters' test files (copyright, flake8, pep257, xmllint, mypy) are
left out: they test the upstream sources, not the API.

The table printed (and `--json`) gives per suite the tests passed of those counted, and per
file the first line of the first failure: what zros lacks, by name.
"""
from __future__ import annotations

import argparse
import ast
import json
import os
import re
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ElementTree
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
_LINTERS = re.compile(r'test_(copyright|flake8|pep257|xmllint|mypy|lint_\w+)\.py$')
_FILE_TIMEOUT = 180


_C_MODULES = ('implementation_singleton', '_rclpy_pybind11')
_C_ATTRIBUTES = {'get_c_qos_profile'}   # returns rmw's C struct of a QoS profile
#: `obj._Node__parameters`: a class-private attribute, as Python mangles `self.__parameters`
_MANGLED = re.compile(r'^_[A-Za-z][A-Za-z0-9]*__[A-Za-z0-9]\w*(?<!__)$')


def defined_tests(path: Path) -> int:
    """The public-API tests a file defines, read from its source: `test*` functions at module
    level and in classes (a class named Test* or any unittest.TestCase), without running
    anything, less the tests of internals (`private_tests`)."""
    tree = _parse(path)
    if tree is None:
        return 0
    private = private_tests(tree)
    return sum(1 for owner, function in _test_functions(tree) if (owner, function.name) not in private)


def _parse(path: Path) -> ast.Module | None:
    try:
        return ast.parse(path.read_text(errors='replace'))
    except SyntaxError:
        return None


def _test_functions(tree: ast.Module):
    """(class name or '', function) for every test the module defines."""
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and node.name.startswith('test'):
            yield '', node
        elif isinstance(node, ast.ClassDef):
            for item in node.body:
                if isinstance(item, (ast.FunctionDef, ast.AsyncFunctionDef)) and item.name.startswith('test'):
                    yield node.name, item


def private_tests(tree: ast.Module) -> set[tuple[str, str]]:
    """The tests of internals rather than the public API, as the issue leaves them out: a test
    that reaches into rclpy's C binding module (`_rclpy.WaitSet`, `_rclpy.Client`, ... imported
    from `rclpy.impl.implementation_singleton`; its exception classes are API and do not count),
    a C struct (`get_c_qos_profile`), or a class-private attribute (`node._Node__parameters`,
    which only the class itself is meant to read), directly or through a helper of the same
    file (a module-level function or class, or a method called on `self`)."""
    bindings = {alias.asname or alias.name for node in ast.walk(tree) if isinstance(node, ast.ImportFrom)
                and any(part in (node.module or '') for part in _C_MODULES) for alias in node.names}

    def touches_c(node: ast.AST, helpers: set[str]) -> bool:
        for sub in ast.walk(node):
            if isinstance(sub, ast.Attribute):
                if sub.attr in _C_ATTRIBUTES or _MANGLED.match(sub.attr):
                    return True
                if isinstance(sub.value, ast.Name):
                    if sub.value.id in bindings and not sub.attr.endswith(('Error', 'Exception')):
                        return True
                    if sub.value.id == 'self' and sub.attr in helpers:
                        return True
            elif isinstance(sub, ast.Name) and sub.id in helpers:
                return True
        return False

    definitions = [(node.name, node) for node in tree.body
                   if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef))]
    definitions += [(item.name, item) for node in tree.body if isinstance(node, ast.ClassDef)
                    for item in node.body if isinstance(item, (ast.FunctionDef, ast.AsyncFunctionDef))
                    and not item.name.startswith('test')]
    helpers: set[str] = set()
    while True:
        grown = {name for name, node in definitions if name not in helpers and touches_c(node, helpers)}
        if not grown:
            break
        helpers |= grown
    return {(owner, function.name) for owner, function in _test_functions(tree)
            if touches_c(function, helpers)}


def run_file(path: Path, env: dict[str, str], work: Path, private: set[tuple[str, str]]) -> dict:
    """Run one test file in its own pytest: passed, failed, and the first failure's line, for
    the tests not in `private` (class name or '', function name)."""
    report = work / (re.sub(r'\W', '_', str(path)) + '.xml')
    command = [sys.executable, '-m', 'zros', 'python', '-m', 'pytest', '-q', '-p', 'no:cacheprovider',
               '-p', 'no:randomly', f'--junitxml={report}', '-o', 'junit_family=xunit2', path.name]
    try:
        result = subprocess.run(command, cwd=path.parent, env=env, capture_output=True, text=True,
                                timeout=_FILE_TIMEOUT, stdin=subprocess.DEVNULL)
        output = result.stdout + result.stderr
    except subprocess.TimeoutExpired:
        return {'passed': 0, 'collected': 0, 'first_failure': f'timed out after {_FILE_TIMEOUT} s'}
    passed = collected = 0
    first = ''
    if report.exists():
        for case in ElementTree.parse(report).getroot().iter('testcase'):
            outcome = next(iter(case), None)
            if outcome is not None and outcome.tag == 'skipped':
                continue
            owner = case.get('classname', '').rpartition('.')[2]
            if (('' if owner == path.stem else owner), case.get('name', '').partition('[')[0]) in private:
                continue
            collected += 1
            if outcome is None:
                passed += 1
            elif not first:
                first = _reason(outcome)
    if not first and result.returncode not in (0, 5):
        errors = [line for line in output.splitlines() if re.search(r'Error|Exception', line)]
        first = _first_line(errors[0] if errors else output or f'exit code {result.returncode}')
    return {'passed': passed, 'collected': collected, 'first_failure': first}


def _reason(outcome: ElementTree.Element) -> str:
    """The line that says why: pytest's message, or for a file it could not import, the
    exception line (`E   ModuleNotFoundError: ...`) of the traceback."""
    message = outcome.get('message') or ''
    if message in ('', 'collection failure') and outcome.text:
        raised = [line[1:].strip() for line in outcome.text.splitlines() if line.startswith('E ')]
        if raised:
            return _first_line(raised[-1])
    return _first_line(message or outcome.text or outcome.tag)


def _first_line(text: str) -> str:
    lines = text.strip().splitlines()
    return lines[0][:200] if lines else ''


def run_suite(name: str, folder: Path, env: dict[str, str], work: Path) -> dict:
    env = dict(env, PYTHONPATH=os.pathsep.join([str(folder), str(folder.parent), env['PYTHONPATH']]))
    files = sorted(p for p in folder.rglob('test_*.py') if not _LINTERS.search(p.name))
    results = {}
    for path in files:
        tree = _parse(path)
        private = private_tests(tree) if tree is not None else set()
        outcome = run_file(path, env, work, private)
        outcome['defined'] = max(defined_tests(path), outcome['collected'])
        outcome['internals'] = len(private)
        results[str(path.relative_to(folder))] = outcome
        left_out = f' ({len(private)} on internals left out)' if private else ''
        print(f'  {name}/{path.relative_to(folder)}: {outcome["passed"]}/{outcome["defined"]}{left_out}'
              f'{"  " + outcome["first_failure"] if outcome["first_failure"] else ""}', flush=True)
    passed = sum(r['passed'] for r in results.values())
    total = sum(r['defined'] for r in results.values())
    return {'passed': passed, 'total': total, 'files': results}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('suites', nargs='+', metavar='SUITE=DIR')
    parser.add_argument('--interfaces', type=Path, default=Path(__file__).parent / 'upstream_interfaces',
                        help='folder of interface packages (test_msgs); default: benchmarks/upstream_interfaces')
    parser.add_argument('--json', type=Path, help='write the results here')
    args = parser.parse_args(argv)
    env = dict(os.environ)
    if args.interfaces:
        env['ZROS_INTERFACE_PATH'] = os.pathsep.join(filter(None, [str(args.interfaces.resolve()),
                                                                   env.get('ZROS_INTERFACE_PATH')]))
    suites = {}
    with tempfile.TemporaryDirectory(prefix='zros-upstream-tests-') as work:
        stubs = Path(work) / 'stubs'
        stubs.mkdir()
        (stubs / 'test_rclpy.py').write_text('"""Stands for rclpy\'s compiled test extension."""\n')
        env['PYTHONPATH'] = os.pathsep.join(filter(None, [str(REPO), str(stubs), env.get('PYTHONPATH')]))
        for spec in args.suites:
            name, _, folder = spec.partition('=')
            if not folder or not Path(folder).is_dir():
                parser.error(f'{spec}: expected SUITE=DIR with an existing folder')
            print(f'{name}:', flush=True)
            suites[name] = run_suite(name, Path(folder).resolve(), env, Path(work))
    print('\n| suite | passed | tests | % |\n|---|---|---|---|')
    for name, suite in suites.items():
        print(f'| {name} | {suite["passed"]} | {suite["total"]} | {100 * suite["passed"] / max(1, suite["total"]):.0f} % |')
    passed = sum(s['passed'] for s in suites.values())
    total = sum(s['total'] for s in suites.values())
    print(f'| **all** | {passed} | {total} | {100 * passed / max(1, total):.0f} % |')
    if args.json:
        args.json.write_text(json.dumps(suites, indent=1))
    return 0


if __name__ == '__main__':
    sys.exit(main())
