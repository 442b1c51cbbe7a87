"""The parameters an rclpy node has and the Node parameter API rclpy's own tests use."""
from __future__ import annotations

import pytest

from zros.exceptions import ParameterImmutableException
from zros.node import Node
from zros.parameter import Parameter
from zros.type_description_service import START_TYPE_DESCRIPTION_SERVICE_PARAM


def test_every_node_declares_the_read_only_type_description_switch(context):
    node = Node('type_description_user', context=context)
    assert node.get_parameter(START_TYPE_DESCRIPTION_SERVICE_PARAM).value is True
    assert node.describe_parameter(START_TYPE_DESCRIPTION_SERVICE_PARAM).read_only
    result, = node.set_parameters([Parameter(START_TYPE_DESCRIPTION_SERVICE_PARAM, value=False)])
    assert not result.successful
    with pytest.raises(ParameterImmutableException):
        node.undeclare_parameter(START_TYPE_DESCRIPTION_SERVICE_PARAM)
    node.destroy_node()
