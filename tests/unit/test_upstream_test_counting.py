"""How benchmarks/upstream_tests.py counts an upstream suite's tests: from the source, once per
test, leaving out those that reach into internals (rclpy's C extension, class-private
attributes) rather than the public API."""
from __future__ import annotations

import ast
import importlib.util
import textwrap
from pathlib import Path

_SPEC = importlib.util.spec_from_file_location(
    'upstream_tests', Path(__file__).resolve().parents[2] / 'benchmarks' / 'upstream_tests.py')
upstream_tests = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(upstream_tests)

_SOURCE = textwrap.dedent('''
    import unittest
    from rclpy.impl.implementation_singleton import rclpy_implementation as _rclpy
    from rclpy.qos import QoSProfile


    class HandleWaitable:
        def __init__(self, node):
            self.handle = _rclpy.GuardCondition(node.context.handle)


    def make_waitable(node):
        return HandleWaitable(node)


    def test_plain_api():
        assert QoSProfile(depth=1).depth == 1


    def test_expects_an_rcl_error():
        try:
            pass
        except _rclpy.RCLError:
            pass


    def test_through_two_helpers(node):
        make_waitable(node)


    class TestProfiles(unittest.TestCase):
        def round_trip(self, profile):
            return profile.get_c_qos_profile()

        def test_uses_the_round_trip(self):
            self.round_trip(QoSProfile(depth=1))

        def test_depth(self):
            assert QoSProfile(depth=2).depth == 2

        def helper_not_a_test(self):
            pass


    def test_reads_a_class_private_attribute(node):
        assert node._Node__parameters == []


    def test_dunder_methods_are_public(node):
        assert node.__class__.__name__ == 'Node'
''')


def test_internals_are_found_directly_and_through_helpers():
    private = upstream_tests.private_tests(ast.parse(_SOURCE))
    assert private == {('', 'test_through_two_helpers'), ('TestProfiles', 'test_uses_the_round_trip'),
                       ('', 'test_reads_a_class_private_attribute')}


def test_defined_tests_counts_the_public_ones(tmp_path):
    path = tmp_path / 'test_sample.py'
    path.write_text(_SOURCE)
    # seven tests, three of them on internals; the binding's exception classes are API
    assert upstream_tests.defined_tests(path) == 4


def test_a_file_python_cannot_parse_defines_nothing(tmp_path):
    path = tmp_path / 'test_broken.py'
    path.write_text('def test_(:\n')
    assert upstream_tests.defined_tests(path) == 0
