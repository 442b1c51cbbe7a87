"""Quality of service: the ROS 2 profiles and what they mean on Zenoh.

A profile is plain data, mutable as rclpy's (`qos.reliability = BEST_EFFORT` is common in
ROS 2 code; every assignment is checked as construction is). A publisher or subscription
copies its profile when it is made (`to_profile`, which also resolves SYSTEM_DEFAULT policies
to the values zros uses), so changing a profile later changes only what is made from it next. The profile is written into a liveliness token
(`to_token` / `from_token`), which is how `zros topic info -v` and the incompatibility check
(and the incompatible-QoS events of zros.event_handler) learn what the other side asked for.

Mapping to Zenoh (see docs/protocol.md):
- RELIABLE -> Zenoh reliable + CongestionControl.BLOCK: the publisher waits rather than lose a
  message silently; only the subscriber's own depth rule drops, and it counts the drops.
- BEST_EFFORT -> CongestionControl.DROP.
- TRANSIENT_LOCAL -> zenoh-ext advanced publisher (cache of `depth`) / advanced subscriber
  (history query for late joiners).
"""
from __future__ import annotations

import enum
import warnings
from dataclasses import dataclass, replace
from typing import Any

from zros.duration import Duration

__all__ = [
    'QoSPolicyEnum', 'HistoryPolicy', 'ReliabilityPolicy', 'DurabilityPolicy', 'LivelinessPolicy', 'QoSPolicyKind',
    'qos_policy_name_from_kind', 'qos_incompatibilities',
    'QoSProfile', 'QoSPresetProfiles', 'Duration', 'InvalidQoSProfileException',
    'qos_profile_default', 'qos_profile_sensor_data', 'qos_profile_services_default',
    'qos_profile_parameters', 'qos_profile_parameter_events', 'qos_profile_system_default',
    'qos_profile_action_status_default', 'qos_profile_best_available', 'qos_profile_unknown',
    'qos_check_compatible', 'QoSCompatibility', 'to_profile',
]


class QoSPolicyEnum(enum.IntEnum):
    """Base of the policy enums: their members by short, lower-case name, as `zros topic pub
    --qos-reliability best_effort` and rclpy's `short_keys()` spell them."""

    @classmethod
    def short_keys(cls) -> list[str]:
        """Every member's name in lower case, in definition order (`['system_default', ...]`)."""
        return [name.lower() for name in cls.__members__]

    @classmethod
    def get_from_short_key(cls, name: str) -> int:
        """The value of the member named `name`, in any case.

        :raises KeyError: If no member has that name.
        """
        return cls[name.upper()].value

    @property
    def short_key(self) -> str:
        """This member's name in lower case."""
        return self.name.lower()


class HistoryPolicy(QoSPolicyEnum):
    """How many samples a reader keeps: the last `depth` (KEEP_LAST) or all (KEEP_ALL).

    zros bounds KEEP_ALL queues at KEEP_ALL_DEPTH, since a Python process has finite memory.
    """
    SYSTEM_DEFAULT = 0
    KEEP_LAST = 1
    KEEP_ALL = 2
    UNKNOWN = 3


class ReliabilityPolicy(QoSPolicyEnum):
    """RELIABLE retransmits and blocks a publisher that is ahead; BEST_EFFORT drops.

    zros maps these onto Zenoh's reliability and congestion control (BLOCK or DROP).
    """
    SYSTEM_DEFAULT = 0
    RELIABLE = 1
    BEST_EFFORT = 2
    UNKNOWN = 3
    BEST_AVAILABLE = 4


class DurabilityPolicy(QoSPolicyEnum):
    """TRANSIENT_LOCAL lets a late subscriber receive the last `depth` samples; VOLATILE does not.

    zros keeps those samples in a Zenoh advanced publisher's cache.
    """
    SYSTEM_DEFAULT = 0
    TRANSIENT_LOCAL = 1
    VOLATILE = 2
    UNKNOWN = 3
    BEST_AVAILABLE = 4


class LivelinessPolicy(QoSPolicyEnum):
    """How a publisher shows it is alive: AUTOMATIC (while its node runs) or MANUAL_BY_TOPIC (by
    publishing or calling `assert_liveliness()` within every lease).
    """
    SYSTEM_DEFAULT = 0
    AUTOMATIC = 1
    MANUAL_BY_TOPIC = 3
    UNKNOWN = 4
    BEST_AVAILABLE = 5


# rclpy spells these both ways; keep the old aliases working.
QoSHistoryPolicy = HistoryPolicy
QoSReliabilityPolicy = ReliabilityPolicy
QoSDurabilityPolicy = DurabilityPolicy
QoSLivelinessPolicy = LivelinessPolicy


class QoSPolicyKind(enum.IntEnum):
    """Which policy an incompatible-QoS event is about (rmw's bit values)."""

    INVALID = 1 << 0
    DURABILITY = 1 << 1
    DEADLINE = 1 << 2
    LIVELINESS = 1 << 3
    RELIABILITY = 1 << 4
    HISTORY = 1 << 5
    LIFESPAN = 1 << 6
    DEPTH = 1 << 7
    LIVELINESS_LEASE_DURATION = 1 << 8
    AVOID_ROS_NAMESPACE_CONVENTIONS = 1 << 9


def qos_policy_name_from_kind(policy_kind: 'QoSPolicyKind | int') -> str:
    """The name of a QoS policy, as QoS events and `zros doctor` print it.

    :param policy_kind: A QoSPolicyKind or its integer value.
    :return: The policy's name, e.g. ``'RELIABILITY'``.
    :raises ValueError: If the value is not a policy kind.
    """
    return QoSPolicyKind(policy_kind).name


#: Keep-all subscriptions still need a bound in Python memory; this is it.
KEEP_ALL_DEPTH = 100_000


class InvalidQoSProfileException(ValueError):
    """A QoS profile that does not say how much history to keep (neither a history nor a depth,
    or KEEP_LAST without a depth)."""


#: The depth of the ROS default profile, which a profile that does not set one gets.
DEFAULT_DEPTH = 10


@dataclass(init=False)
class QoSProfile:
    """A ROS 2 QoS profile. `QoSProfile(depth=10)` is the ROS default profile. As in rclpy, a
    profile must say how much history it keeps: a `depth` (KEEP_LAST is then implied), or a
    `history` (KEEP_LAST still needs a depth), so that nobody gets a queue length they did not
    choose. The durations (zros.duration.Duration, as rclpy's) are 0 for 'not set': no deadline,
    infinite lifespan and lease. Profiles compare by value and, being mutable, are not hashable
    (as rclpy's)."""

    history: HistoryPolicy
    depth: int
    reliability: ReliabilityPolicy
    durability: DurabilityPolicy
    liveliness: LivelinessPolicy
    deadline: Duration
    lifespan: Duration
    liveliness_lease_duration: Duration
    avoid_ros_namespace_conventions: bool

    def __init__(self, *, history: HistoryPolicy | int | None = None, depth: int | None = None,
                 reliability: ReliabilityPolicy | int = ReliabilityPolicy.RELIABLE,
                 durability: DurabilityPolicy | int = DurabilityPolicy.VOLATILE,
                 liveliness: LivelinessPolicy | int = LivelinessPolicy.AUTOMATIC,
                 deadline: Duration = Duration(), lifespan: Duration = Duration(),
                 liveliness_lease_duration: Duration = Duration(),
                 avoid_ros_namespace_conventions: bool = False) -> None:
        """Raises InvalidQoSProfileException when neither `history` nor `depth` is given, or
        `history` is KEEP_LAST and `depth` is not; ValueError for a value of the wrong kind."""
        if history is None:
            if depth is None:
                raise InvalidQoSProfileException('a QoS profile needs a history, a depth or both')
            history = HistoryPolicy.KEEP_LAST
        elif depth is None:
            if history == HistoryPolicy.KEEP_LAST:
                raise InvalidQoSProfileException('a QoS profile with KEEP_LAST history needs a depth')
            depth = DEFAULT_DEPTH
        # plain ints become the policies in __setattr__; in this order: the depth's check reads the history
        self.history, self.depth = HistoryPolicy(history), depth
        self.reliability, self.durability = ReliabilityPolicy(reliability), DurabilityPolicy(durability)
        self.liveliness = LivelinessPolicy(liveliness)
        self.deadline, self.lifespan = deadline, lifespan
        self.liveliness_lease_duration = liveliness_lease_duration
        self.avoid_ros_namespace_conventions = avoid_ros_namespace_conventions

    def __setattr__(self, name: str, value: object) -> None:
        # Plain ints are accepted for the policies, as rclpy does. SYSTEM_DEFAULT stays as given
        # (rclpy compares and prints it so); an entity resolves it when it copies the profile.
        policy = _POLICIES.get(name)
        if policy is not None:
            value = policy(value)
        elif name == 'depth':
            if isinstance(value, bool) or not isinstance(value, int) or value < 0:
                raise ValueError(f'QoS depth must be greater than or equal to zero, got {value!r}')
            if value == 0 and self.history == HistoryPolicy.KEEP_LAST:
                warnings.warn("A zero depth with KEEP_LAST doesn't make sense; no data could be stored. "
                              f'zros keeps the default depth ({DEFAULT_DEPTH}) instead', UserWarning, stacklevel=2)
        object.__setattr__(self, name, value)

    @property
    def queue_depth(self) -> int:
        """Length of the per-subscription queue this profile asks for (KEEP_LAST with a depth of
        0 means the system default, as in ROS: the default depth)."""
        if self.history == HistoryPolicy.KEEP_ALL:
            return KEEP_ALL_DEPTH
        return self.depth or DEFAULT_DEPTH

    def to_token(self) -> str:
        """Compact text for liveliness tokens: `R|B : V|T : L<depth>|A`, then only what is
        not the default: `:D<ns>` deadline, `:S<ns>` lifespan, `:M` manual-by-topic
        liveliness, `:E<ns>` liveliness lease duration."""
        rel = 'B' if self.reliability == ReliabilityPolicy.BEST_EFFORT else 'R'
        dur = 'T' if self.durability == DurabilityPolicy.TRANSIENT_LOCAL else 'V'
        hist = 'A' if self.history == HistoryPolicy.KEEP_ALL else f'L{self.queue_depth}'
        parts = [rel, dur, hist]
        for tag, value in (('D', self.deadline), ('S', self.lifespan)):
            if value.nanoseconds > 0:
                parts.append(f'{tag}{value.nanoseconds}')
        if self.liveliness == LivelinessPolicy.MANUAL_BY_TOPIC:
            parts.append('M')
        if self.liveliness_lease_duration.nanoseconds > 0:
            parts.append(f'E{self.liveliness_lease_duration.nanoseconds}')
        return ':'.join(parts)

    @classmethod
    def from_token(cls, text: str) -> 'QoSProfile':
        """Parse the text `to_token` writes, as read from another participant's liveliness token.

        :param text: The token text.
        :return: The profile; the default profile if the text is malformed (a foreign token must
            not break graph queries; so is an empty text, what a bag without QoS records holds).
        """
        try:
            rel, dur, hist, *extra = text.split(':')
            depth = 0 if hist == 'A' else int(hist[1:])
            if hist != 'A' and depth < 1:
                raise ValueError(f'a KEEP_LAST token needs a depth of 1 or more: {hist}')
            durations = {'D': 'deadline', 'S': 'lifespan', 'E': 'liveliness_lease_duration'}
            optional: dict[str, Any] = {durations[item[0]]: Duration(nanoseconds=int(item[1:]))
                        for item in extra if item[:1] in durations}
            return cls(
                reliability=ReliabilityPolicy.BEST_EFFORT if rel == 'B' else ReliabilityPolicy.RELIABLE,
                durability=DurabilityPolicy.TRANSIENT_LOCAL if dur == 'T' else DurabilityPolicy.VOLATILE,
                history=HistoryPolicy.KEEP_ALL if hist == 'A' else HistoryPolicy.KEEP_LAST,
                depth=depth,
                liveliness=LivelinessPolicy.MANUAL_BY_TOPIC if 'M' in extra else LivelinessPolicy.AUTOMATIC,
                **optional,
            )
        except (ValueError, IndexError):
            return cls(depth=DEFAULT_DEPTH)


_POLICIES: dict[str, Any] = {'history': HistoryPolicy, 'reliability': ReliabilityPolicy,
                              'durability': DurabilityPolicy, 'liveliness': LivelinessPolicy}
_SYSTEM_DEFAULTS = {'history': HistoryPolicy.KEEP_LAST, 'reliability': ReliabilityPolicy.RELIABLE,
                    'durability': DurabilityPolicy.VOLATILE, 'liveliness': LivelinessPolicy.AUTOMATIC}

qos_profile_default = QoSProfile(depth=10)
qos_profile_sensor_data = QoSProfile(depth=5, reliability=ReliabilityPolicy.BEST_EFFORT)
qos_profile_services_default = QoSProfile(depth=10)
qos_profile_parameters = QoSProfile(depth=1000)
qos_profile_parameter_events = QoSProfile(depth=1000)
qos_profile_system_default = QoSProfile(
    history=HistoryPolicy.SYSTEM_DEFAULT, depth=0, reliability=ReliabilityPolicy.SYSTEM_DEFAULT,
    durability=DurabilityPolicy.SYSTEM_DEFAULT, liveliness=LivelinessPolicy.SYSTEM_DEFAULT)
qos_profile_action_status_default = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
qos_profile_best_available = QoSProfile(depth=10)
#: What an endpoint's QoS is when nothing is known of it (rmw's qos_profile_unknown).
qos_profile_unknown = QoSProfile(history=HistoryPolicy.UNKNOWN, depth=0, reliability=ReliabilityPolicy.UNKNOWN,
                                 durability=DurabilityPolicy.UNKNOWN, liveliness=LivelinessPolicy.UNKNOWN)


class QoSPresetProfiles(enum.Enum):
    """The named profiles, so that `zros topic pub --qos-profile sensor_data` can look one up."""
    DEFAULT = qos_profile_default
    SENSOR_DATA = qos_profile_sensor_data
    SERVICES_DEFAULT = qos_profile_services_default
    PARAMETERS = qos_profile_parameters
    PARAMETER_EVENTS = qos_profile_parameter_events
    SYSTEM_DEFAULT = qos_profile_system_default
    ACTION_STATUS_DEFAULT = qos_profile_action_status_default
    BEST_AVAILABLE = qos_profile_best_available
    UNKNOWN = qos_profile_unknown

    @classmethod
    def get_from_short_key(cls, name: str) -> QoSProfile:
        """Look a preset up by its short name, in any case.

        :param name: E.g. ``'sensor_data'`` or ``'services_default'``.
        :return: The profile.
        :raises KeyError: If there is no preset of that name.
        """
        return cls[name.upper()].value


def to_profile(qos: 'QoSProfile | int') -> QoSProfile:
    """The profile an entity keeps: a copy of `qos` with each SYSTEM_DEFAULT policy replaced by
    the value zros uses (RELIABLE, VOLATILE, KEEP_LAST, AUTOMATIC), or, as rclpy accepts a depth
    where a profile is expected, KEEP_LAST with that depth."""
    if isinstance(qos, QoSProfile):
        changes: dict[str, Any] = {name: resolved for name, resolved in _SYSTEM_DEFAULTS.items()
                                   if getattr(qos, name) == _POLICIES[name].SYSTEM_DEFAULT}
        if 'history' in changes and qos.depth == 0:
            changes['depth'] = DEFAULT_DEPTH     # the system default depth, as queue_depth has it
        return replace(qos, **changes)
    if isinstance(qos, bool) or not isinstance(qos, int):
        raise TypeError(f'Expected QoSProfile or int (a depth), but received {type(qos).__name__}')
    return replace(qos_profile_default, depth=qos)


class QoSCompatibility(enum.IntEnum):
    """The verdict of `qos_check_compatible` on a publisher/subscription pair."""
    OK = 0
    WARNING = 1
    ERROR = 2


def qos_incompatibilities(publisher: QoSProfile, subscription: QoSProfile) -> list[tuple[QoSPolicyKind, str]]:
    """Every DDS request/offer rule the pair breaks, as (policy, rmw's reason text). A
    SYSTEM_DEFAULT policy breaks none (qos_check_compatible doubts it); entities' profiles have
    none left (to_profile resolves them)."""
    found = []
    if (publisher.reliability == ReliabilityPolicy.BEST_EFFORT
            and subscription.reliability == ReliabilityPolicy.RELIABLE):
        found.append((QoSPolicyKind.RELIABILITY, 'ERROR: Best effort publisher and reliable subscription;'))
    if (publisher.durability == DurabilityPolicy.VOLATILE
            and subscription.durability == DurabilityPolicy.TRANSIENT_LOCAL):
        found.append((QoSPolicyKind.DURABILITY, 'ERROR: Volatile publisher and transient local subscription;'))
    offered, requested = publisher.deadline.nanoseconds, subscription.deadline.nanoseconds
    if requested and not offered:
        found.append((QoSPolicyKind.DEADLINE, 'ERROR: Subscription has a deadline, but publisher does not;'))
    elif requested and offered > requested:
        found.append((QoSPolicyKind.DEADLINE, 'ERROR: Subscription deadline is less than publisher deadline;'))
    if (publisher.liveliness == LivelinessPolicy.AUTOMATIC
            and subscription.liveliness == LivelinessPolicy.MANUAL_BY_TOPIC):
        found.append((QoSPolicyKind.LIVELINESS,
                      'ERROR: Publisher\'s liveliness is automatic and subscription\'s is manual by topic;'))
    offered, requested = (publisher.liveliness_lease_duration.nanoseconds,
                          subscription.liveliness_lease_duration.nanoseconds)
    if requested and not offered:
        found.append((QoSPolicyKind.LIVELINESS_LEASE_DURATION,
                      'ERROR: Subscription has a liveliness lease duration, but publisher does not;'))
    elif requested and offered > requested:
        found.append((QoSPolicyKind.LIVELINESS_LEASE_DURATION,
                      'ERROR: Subscription liveliness lease duration is less than publisher;'))
    return found


def qos_check_compatible(publisher: QoSProfile, subscription: QoSProfile) -> tuple[QoSCompatibility, str]:
    """The DDS request/offer rules ROS 2 reports (rclpy.qos.qos_check_compatible).

    zros still delivers across such pairs where Zenoh can, but reports them so that a ROS 2
    user sees the same warnings (and `zros doctor` can list them). A pair that only matches
    because of a SYSTEM_DEFAULT policy is a WARNING, as in ROS: the code may run on a middleware
    whose default is another.
    """
    found = qos_incompatibilities(publisher, subscription)
    if found:
        return QoSCompatibility.ERROR, ' '.join(reason for _, reason in found)
    possible = _system_default_doubts(publisher, subscription)
    if possible:
        return QoSCompatibility.WARNING, ' '.join(possible)
    return QoSCompatibility.OK, ''


# policy attribute, the publisher's value and the subscription's value that break the rule
_OFFER_RULES = (('reliability', ReliabilityPolicy.BEST_EFFORT, ReliabilityPolicy.RELIABLE),
                ('durability', DurabilityPolicy.VOLATILE, DurabilityPolicy.TRANSIENT_LOCAL),
                ('liveliness', LivelinessPolicy.AUTOMATIC, LivelinessPolicy.MANUAL_BY_TOPIC))


def _system_default_doubts(publisher: QoSProfile, subscription: QoSProfile) -> list[str]:
    """rmw's warnings: a rule that a SYSTEM_DEFAULT policy on one side might break."""
    doubts = []
    for name, offered, requested in _OFFER_RULES:
        pub, sub = getattr(publisher, name), getattr(subscription, name)
        default = type(pub).SYSTEM_DEFAULT
        if pub == default and sub == requested:
            doubts.append(f'WARNING: Publisher {name} is SYSTEM_DEFAULT and subscription is {sub.name};')
        elif pub == offered and sub == default:
            doubts.append(f'WARNING: Publisher {name} is {pub.name} and subscription is SYSTEM_DEFAULT;')
    return doubts
