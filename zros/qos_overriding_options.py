"""QoS overrides from parameters, as rclpy.qos_overriding_options.

A publisher or subscription made with `qos_overriding_options=` declares one read-only
parameter per chosen policy, `qos_overrides.<topic>.<publisher|subscription>[_<id>].<policy>`,
whose default is the code's value. A value given at start-up (`-p`, a parameter file, a launch
file) replaces it, so the QoS of a compiled-in topic can be changed without editing the code:

    talker:
      ros__parameters:
        qos_overrides:
          /chatter:
            publisher:
              reliability: best_effort
              depth: 5
"""
from __future__ import annotations

from dataclasses import fields, replace
from typing import TYPE_CHECKING, Any, Callable, Iterable

from zros.duration import Duration
from zros.errors import ZrosError
from zros.exceptions import ParameterAlreadyDeclaredException
from zros.qos import DurabilityPolicy, HistoryPolicy, LivelinessPolicy, QoSPolicyKind, QoSProfile, ReliabilityPolicy
from zros.subscription import Subscription

if TYPE_CHECKING:
    from zros.node import Node

__all__ = ['QoSOverridingOptions', 'QosCallbackResult',  # noqa: F822 - QosCallbackResult comes from __getattr__ 'QosCallbackType', 'InvalidQosOverridesError',
           'declare_qos_parameters', 'parameter_events_overriding_options']
# rclpy's private helpers `_declare_qos_parameters` and `_get_qos_policy_parameter` are defined
# here too: tests and tools written for rclpy call them.


class InvalidQosOverridesError(ZrosError):
    """The overridden QoS was refused by the options' callback, or a value is not a policy's."""


QosCallbackType = Callable[[QoSProfile], Any]


def __getattr__(name: str) -> Any:
    """`QosCallbackResult`, what a QoS callback returns, is rcl_interfaces' SetParametersResult
    (as in rclpy); loaded on first use so that importing zros.node loads no message class."""
    if name == 'QosCallbackResult':
        from interfaces.rcl_interfaces.msg import SetParametersResult
        return SetParametersResult
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

# policy -> the enum its parameter names (lower case), None for plain values
_ENUMS = {QoSPolicyKind.HISTORY: HistoryPolicy, QoSPolicyKind.RELIABILITY: ReliabilityPolicy,
          QoSPolicyKind.DURABILITY: DurabilityPolicy, QoSPolicyKind.LIVELINESS: LivelinessPolicy}
_DURATIONS = (QoSPolicyKind.DEADLINE, QoSPolicyKind.LIFESPAN, QoSPolicyKind.LIVELINESS_LEASE_DURATION)


class QoSOverridingOptions:
    """Which QoS policies of one publisher or subscription may be overridden by parameters."""

    def __init__(self, policy_kinds: Iterable[QoSPolicyKind], *, callback: QosCallbackType | None = None,
                 entity_id: str | None = None) -> None:
        """Args:
            policy_kinds: the policies that get a parameter.
            callback: validates the overridden profile; returns a SetParametersResult.
            entity_id: tells apart two endpoints of one node on one topic (a `_<id>` suffix).
        """
        self._policy_kinds = list(policy_kinds)
        self._callback = callback
        self._entity_id = entity_id

    @property
    def policy_kinds(self) -> list[QoSPolicyKind]:
        return self._policy_kinds

    @property
    def callback(self) -> QosCallbackType | None:
        return self._callback

    @property
    def entity_id(self) -> str | None:
        return self._entity_id

    @classmethod
    def with_default_policies(cls, *, callback: QosCallbackType | None = None,
                              entity_id: str | None = None) -> 'QoSOverridingOptions':
        """History, depth and reliability, as rclpy."""
        return cls((QoSPolicyKind.HISTORY, QoSPolicyKind.DEPTH, QoSPolicyKind.RELIABILITY),
                   callback=callback, entity_id=entity_id)


def parameter_events_overriding_options() -> QoSOverridingOptions:
    """What every rclcpp node declares for its /parameter_events publisher (rclpy nodes declare
    nothing): `qos_overrides./parameter_events.publisher.depth|durability|history|reliability`,
    which `ros2 param list /turtlesim` shows."""
    return QoSOverridingOptions((QoSPolicyKind.DEPTH, QoSPolicyKind.DURABILITY, QoSPolicyKind.HISTORY,
                                 QoSPolicyKind.RELIABILITY))


def declare_qos_parameters(entity_type: type, node: 'Node', topic: str, qos: QoSProfile,
                           options: QoSOverridingOptions | None) -> QoSProfile:
    """Declare the override parameters of one endpoint and return its QoS with their values.

    Raises:
        InvalidQosOverridesError: a value that is not one of its policy's, or a profile the
            options' callback refuses.
    """
    if options is None:
        return qos
    from interfaces.rcl_interfaces.msg import ParameterDescriptor
    kind = 'subscription' if issubclass(entity_type, Subscription) else 'publisher'
    suffix = '' if options.entity_id is None else f'_{options.entity_id}'
    prefix = f'qos_overrides.{topic}.{kind}{suffix}'
    changes: dict[str, Any] = {}
    for policy in options.policy_kinds:
        policy = QoSPolicyKind(policy)
        if policy in (QoSPolicyKind.INVALID,) or (kind == 'subscription' and policy == QoSPolicyKind.LIFESPAN):
            continue
        attribute = policy.name.lower()
        name = f'{prefix}.{attribute}'
        descriptor = ParameterDescriptor(description=f'{attribute} for {kind} `{topic}` with id `{options.entity_id}`',
                                         read_only=True)
        try:
            param = node.declare_parameter(name, _get_qos_policy_parameter(qos, policy), descriptor)
        except ParameterAlreadyDeclaredException:
            param = node.get_parameter(name)
        changes[attribute] = _policy_value(policy, param.value, name)
    try:
        overridden = replace(qos, **changes)
    except ValueError as exc:
        raise InvalidQosOverridesError(f'QoS overrides for {kind} `{topic}` are not valid: {exc}') from None
    if options.callback is not None:
        result = options.callback(overridden)
        if not result.successful:
            raise InvalidQosOverridesError(
                f'Provided QoS overrides for {kind} `{topic}` with id `{options.entity_id}`, are not valid: '
                f'{result.reason}')
    return overridden


def _declare_qos_parameters(entity_type: type, node: 'Node', topic_name: str, qos: QoSProfile,
                            options: QoSOverridingOptions) -> None:
    """rclpy's form of `declare_qos_parameters`: the overridden values are written into `qos`
    itself (the caller's profile), instead of into a copy that is returned."""
    overridden = declare_qos_parameters(entity_type, node, topic_name, qos, options)
    for field in fields(QoSProfile):
        setattr(qos, field.name, getattr(overridden, field.name))


def _get_qos_policy_parameter(qos: QoSProfile, policy: QoSPolicyKind) -> Any:
    """The parameter value one policy of `qos` is declared with: a policy's lower-case name
    (`'best_effort'`), a duration's nanoseconds, the depth itself.

    Raises:
        ValueError: The policy is UNKNOWN, which no parameter can say.
    """
    value = getattr(qos, QoSPolicyKind(policy).name.lower())
    if isinstance(value, (HistoryPolicy, ReliabilityPolicy, DurabilityPolicy, LivelinessPolicy)):
        if value.name == 'UNKNOWN':
            raise ValueError(f'the QoS profile has an UNKNOWN {QoSPolicyKind(policy).name.lower()} policy')
        return value.name.lower()
    if isinstance(value, Duration):
        return value.nanoseconds
    return value


def _policy_value(policy: QoSPolicyKind, value: Any, name: str) -> Any:
    enum_type = _ENUMS.get(policy)
    if enum_type is not None:
        try:
            return enum_type[str(value).upper()]
        except KeyError:
            choices = ', '.join(m.name.lower() for m in enum_type if m.name not in ('UNKNOWN', 'SYSTEM_DEFAULT'))
            raise InvalidQosOverridesError(f"parameter '{name}': '{value}' is not one of {choices}") from None
    if policy in _DURATIONS:
        return Duration(nanoseconds=int(value))
    return value
