"""zros.Context as rclpy's tests and programs use it: a `with` block initializes and shuts it down."""
from __future__ import annotations

from zros.context import Context


def test_with_block_initializes_then_shuts_down(domain):
    context = Context()
    assert not context.ok()
    with context as entered:
        assert entered is context and context.ok()
    assert not context.ok()
    context.try_shutdown()   # harmless afterwards
    context.destroy()


def test_with_block_keeps_an_initialized_context(make_context):
    context = make_context()
    with context:
        assert context.ok()
    assert not context.ok()
