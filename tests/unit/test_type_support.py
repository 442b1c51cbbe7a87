"""rclpy.type_support and rclpy.type_hash over zros's interface classes."""
from __future__ import annotations

import pytest

from interfaces.std_msgs.msg import String
from interfaces.std_srvs.srv import Trigger
from zros.exceptions import NoTypeSupportImportedException
from zros.type_hash import TypeHash
from zros.type_support import check_for_type_support, check_is_valid_msg_type, check_is_valid_srv_type


def test_zros_classes_have_type_support_and_are_told_apart():
    check_for_type_support(String)
    check_for_type_support(String())   # an instance too
    check_for_type_support(Trigger)
    with pytest.raises(AttributeError, match='no type support'):
        check_for_type_support(dict)
    check_is_valid_msg_type(String)
    check_is_valid_srv_type(Trigger)
    with pytest.raises(RuntimeError, match='might be a service'):
        check_is_valid_msg_type(Trigger)
    with pytest.raises(RuntimeError, match='might be a message'):
        check_is_valid_srv_type(String)


def test_an_object_without_type_support_and_a_class_whose_support_stays_empty_are_refused():
    with pytest.raises(AttributeError, match='ROS 1'):
        check_for_type_support(object())

    class EmptySupport(type):
        _TYPE_SUPPORT = None
        imported = 0

        @classmethod
        def __import_type_support__(cls):
            cls.imported += 1

    class Generated(metaclass=EmptySupport):
        pass
    with pytest.raises(NoTypeSupportImportedException):
        check_for_type_support(Generated)
    assert EmptySupport.imported == 1   # asked to import before giving up


def test_type_hash_text_round_trip_and_the_invalid_hash():
    digest = bytes(range(32))
    text = 'RIHS01_' + digest.hex()
    assert str(TypeHash(1, digest)) == text and TypeHash.from_string(text) == TypeHash(1, digest)
    assert str(TypeHash()) == 'INVALID' and TypeHash.from_string('bde7214dc1581c71') == TypeHash()
    assert TypeHash(version=5) != TypeHash() and {TypeHash(), TypeHash()} == {TypeHash()}
    with pytest.raises(TypeError):
        TypeHash(1, 'not bytes')
