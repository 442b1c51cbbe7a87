"""zros.qos: profiles, presets, the token form used in the graph, and compatibility."""
from __future__ import annotations

import pytest

from zros.qos import (KEEP_ALL_DEPTH, DurabilityPolicy, HistoryPolicy, InvalidQoSProfileException, LivelinessPolicy, QoSCompatibility,
                      QoSPresetProfiles, QoSProfile, ReliabilityPolicy, qos_check_compatible,
                      qos_profile_action_status_default, qos_profile_default, qos_profile_parameters,
                      qos_profile_sensor_data, qos_profile_services_default, qos_profile_system_default,
                      to_profile)

RELIABLE, BEST_EFFORT = ReliabilityPolicy.RELIABLE, ReliabilityPolicy.BEST_EFFORT
VOLATILE, TRANSIENT_LOCAL = DurabilityPolicy.VOLATILE, DurabilityPolicy.TRANSIENT_LOCAL


def test_a_profile_must_say_how_much_history_it_keeps():
    with pytest.raises(InvalidQoSProfileException):
        QoSProfile()
    with pytest.raises(InvalidQoSProfileException):
        QoSProfile(history=HistoryPolicy.KEEP_LAST, reliability=BEST_EFFORT)
    assert QoSProfile(history=HistoryPolicy.KEEP_ALL).history == HistoryPolicy.KEEP_ALL


def test_keep_last_with_zero_depth_warns_and_queues_the_default_depth():
    with pytest.warns(UserWarning, match="zero depth with KEEP_LAST"):
        profile = QoSProfile(depth=0)
    assert profile.queue_depth == 10 and profile.to_token() == 'R:V:L10'
    with pytest.warns(UserWarning, match="zero depth with KEEP_LAST"):
        QoSProfile(depth=3).depth = 0


def test_policy_short_keys():
    assert ReliabilityPolicy.short_keys()[:3] == ['system_default', 'reliable', 'best_effort']
    assert DurabilityPolicy.get_from_short_key('Transient_Local') == DurabilityPolicy.TRANSIENT_LOCAL.value
    assert LivelinessPolicy.MANUAL_BY_TOPIC.short_key == 'manual_by_topic'


def test_default_profile_is_ros_default():
    profile = QoSProfile(depth=10)
    assert (profile.history, profile.depth, profile.reliability, profile.durability, profile.liveliness) == \
        (HistoryPolicy.KEEP_LAST, 10, RELIABLE, VOLATILE, LivelinessPolicy.AUTOMATIC)
    assert QoSProfile(depth=10) == qos_profile_default


def test_presets():
    assert (qos_profile_sensor_data.reliability, qos_profile_sensor_data.depth) == (BEST_EFFORT, 5)
    assert qos_profile_sensor_data.durability == VOLATILE
    assert qos_profile_parameters.depth == 1000 and qos_profile_parameters.reliability == RELIABLE
    assert qos_profile_services_default.reliability == RELIABLE
    assert qos_profile_system_default.history == HistoryPolicy.SYSTEM_DEFAULT
    assert to_profile(qos_profile_system_default) == qos_profile_default
    assert qos_profile_action_status_default.durability == TRANSIENT_LOCAL
    assert QoSPresetProfiles.SENSOR_DATA.value is qos_profile_sensor_data
    assert QoSPresetProfiles.get_from_short_key('sensor_data') is qos_profile_sensor_data
    assert QoSPresetProfiles.get_from_short_key('SYSTEM_DEFAULT') == qos_profile_system_default
    with pytest.raises(KeyError):
        QoSPresetProfiles.get_from_short_key('nope')


def test_plain_ints_are_policies_and_entities_resolve_system_default():
    profile = QoSProfile(reliability=2, durability=1, history=1, depth=4)
    assert (profile.reliability, profile.durability) == (BEST_EFFORT, TRANSIENT_LOCAL)
    assert isinstance(profile.reliability, ReliabilityPolicy)
    system = QoSProfile(history=HistoryPolicy.SYSTEM_DEFAULT, reliability=ReliabilityPolicy.SYSTEM_DEFAULT,
                        durability=DurabilityPolicy.SYSTEM_DEFAULT, liveliness=LivelinessPolicy.SYSTEM_DEFAULT)
    assert system != QoSProfile(depth=10) and system.reliability == ReliabilityPolicy.SYSTEM_DEFAULT
    assert to_profile(system) == QoSProfile(depth=10) and system.to_token() == 'R:V:L10'


def test_a_match_that_rests_on_a_system_default_is_a_warning():
    reliable = QoSProfile(depth=1, reliability=RELIABLE)
    assert qos_check_compatible(qos_profile_system_default, reliable)[0] == QoSCompatibility.WARNING
    best_effort = QoSProfile(depth=1, reliability=BEST_EFFORT)
    compatibility, reason = qos_check_compatible(best_effort, qos_profile_system_default)
    assert compatibility == QoSCompatibility.WARNING and 'SYSTEM_DEFAULT' in reason
    assert qos_check_compatible(qos_profile_system_default, qos_profile_system_default)[0] == QoSCompatibility.OK


@pytest.mark.parametrize('kwargs', [dict(depth=-1), dict(depth=1.5), dict(reliability=99)])
def test_invalid_profiles(kwargs):
    with pytest.raises(ValueError):
        QoSProfile(**kwargs)


def test_keep_all():
    profile = QoSProfile(history=HistoryPolicy.KEEP_ALL, depth=0)
    assert profile.queue_depth == KEEP_ALL_DEPTH
    assert QoSProfile(depth=7).queue_depth == 7


def test_to_profile():
    assert to_profile(5) == QoSProfile(depth=5)
    copy = to_profile(qos_profile_sensor_data)
    assert copy == qos_profile_sensor_data and copy is not qos_profile_sensor_data
    for bad in (True, '10', 1.0, None):
        with pytest.raises(TypeError):
            to_profile(bad)
    with pytest.warns(UserWarning):
        assert to_profile(0).queue_depth == 10     # rclpy: KEEP_LAST 0 means the system default


@pytest.mark.parametrize('profile, token', [
    (QoSProfile(depth=10), 'R:V:L10'),
    (qos_profile_sensor_data, 'B:V:L5'),
    (QoSProfile(depth=1, durability=TRANSIENT_LOCAL), 'R:T:L1'),
    (QoSProfile(history=HistoryPolicy.KEEP_ALL, depth=0), 'R:V:A'),
    (QoSProfile(depth=123, reliability=BEST_EFFORT, durability=TRANSIENT_LOCAL), 'B:T:L123'),
])
def test_token_round_trip(profile, token):
    assert profile.to_token() == token
    assert QoSProfile.from_token(token) == profile
    # a token is one key chunk: no '/', and no Zenoh wildcard characters
    assert not set(token) & set('/*$#?')


@pytest.mark.parametrize('garbage', ['', 'R:V', 'X:Y:Z', 'R:V:Lx', 'R:V:L0', 'a:b:c:d'])
def test_from_token_falls_back_to_default(garbage):
    assert QoSProfile.from_token(garbage) == QoSProfile(depth=10)


@pytest.mark.parametrize('pub, sub, expected', [
    (QoSProfile(depth=10), QoSProfile(depth=10), QoSCompatibility.OK),
    (QoSProfile(depth=10, reliability=RELIABLE), QoSProfile(depth=10, reliability=BEST_EFFORT), QoSCompatibility.OK),
    (QoSProfile(depth=10, reliability=BEST_EFFORT), QoSProfile(depth=10, reliability=RELIABLE), QoSCompatibility.ERROR),
    (QoSProfile(depth=10, reliability=BEST_EFFORT), QoSProfile(depth=10, reliability=BEST_EFFORT), QoSCompatibility.OK),
    (QoSProfile(depth=10, durability=TRANSIENT_LOCAL), QoSProfile(depth=10, durability=VOLATILE), QoSCompatibility.OK),
    (QoSProfile(depth=10, durability=VOLATILE), QoSProfile(depth=10, durability=TRANSIENT_LOCAL), QoSCompatibility.ERROR),
    (QoSProfile(depth=10, durability=TRANSIENT_LOCAL), QoSProfile(depth=10, durability=TRANSIENT_LOCAL), QoSCompatibility.OK),
    (qos_profile_sensor_data, qos_profile_default, QoSCompatibility.ERROR),
    (qos_profile_default, qos_profile_sensor_data, QoSCompatibility.OK),
])
def test_compatibility(pub, sub, expected):
    result, reason = qos_check_compatible(pub, sub)
    assert result == expected
    if expected == QoSCompatibility.ERROR:
        assert reason.startswith('ERROR:')
    else:
        assert reason == ''


def test_reliability_reason_names_the_policies():
    _, reason = qos_check_compatible(QoSProfile(depth=10, reliability=BEST_EFFORT), QoSProfile(depth=10))
    assert 'Best effort publisher and reliable subscription' in reason
    _, reason = qos_check_compatible(QoSProfile(depth=10), QoSProfile(depth=10, durability=TRANSIENT_LOCAL))
    assert 'Volatile publisher and transient local subscription' in reason


def test_a_negative_depth_is_refused_in_rclpys_words():
    with pytest.raises(ValueError, match='must be greater than or equal to zero'):
        QoSProfile(depth=-1)


def test_override_parameters_spell_policies_as_rclpy():
    from zros.qos import Duration, QoSPolicyKind, qos_profile_unknown
    from zros.qos_overriding_options import _get_qos_policy_parameter
    profile = QoSProfile(depth=7, liveliness=LivelinessPolicy.SYSTEM_DEFAULT, deadline=Duration(seconds=1))
    assert _get_qos_policy_parameter(profile, QoSPolicyKind.LIVELINESS) == 'system_default'
    assert _get_qos_policy_parameter(profile, QoSPolicyKind.DEADLINE) == 1_000_000_000
    assert _get_qos_policy_parameter(profile, QoSPolicyKind.DEPTH) == 7
    with pytest.raises(ValueError):
        _get_qos_policy_parameter(qos_profile_unknown, QoSPolicyKind.RELIABILITY)
