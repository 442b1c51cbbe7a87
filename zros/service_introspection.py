"""Service introspection, as rclpy.service_introspection: a service or a client, once configured,
publishes what happens to each call on `<service>/_service_event`.

Four events make one call: the client sent the request, the server received it, the server sent
the response, the client received it. Each names the client (its writer id, the gid of the
request's attachment) and the request's sequence number, so the four can be matched up; with
CONTENTS the request or response rides along. Off by default: introspection costs a publish
per event.
"""
from __future__ import annotations

import enum
import threading
from typing import TYPE_CHECKING, Any

from zros.qos import QoSProfile
from zros.wire import read_header

if TYPE_CHECKING:
    from zros.clock import Clock
    from zros.publisher import Publisher

__all__ = ['ServiceIntrospectionState', 'ServiceIntrospection', 'Introspectable', 'call_origin']

#: The event topic under a service's name (hidden: it starts with an underscore).
EVENT_SUFFIX = '/_service_event'
# service_msgs/msg/ServiceEventInfo's event types
REQUEST_SENT, REQUEST_RECEIVED, RESPONSE_SENT, RESPONSE_RECEIVED = range(4)


class ServiceIntrospectionState(enum.IntEnum):
    """What introspection publishes: nothing, the events alone, or the events with the request
    or response (rcl's RCL_SERVICE_INTROSPECTION_* values)."""
    OFF = 0
    METADATA = 1
    CONTENTS = 2


def call_origin(attachment: bytes) -> tuple[bytes, int]:
    """(client gid, sequence number) of a request, from the attachment its client stamped; zeros
    for a request from a writer that stamps none."""
    header = read_header(attachment)
    return (header[0], header[1]) if header is not None else (bytes(16), 0)


class ServiceIntrospection:
    """The event publisher of one service or client. Made by `configure_introspection`; the
    entity calls `record` from whichever thread the call's step happens on."""

    def __init__(self, entity: Any) -> None:
        self._entity = entity
        self._lock = threading.Lock()
        self._publisher: Publisher[Any] | None = None
        self._clock: Clock | None = None
        self._state = ServiceIntrospectionState.OFF

    def configure(self, clock: Clock, qos: QoSProfile, state: ServiceIntrospectionState | int) -> None:
        """Start, change or stop (OFF) publishing; a new QoS replaces the event publisher."""
        state = ServiceIntrospectionState(state)
        node = self._entity._node
        with self._lock:
            old, self._publisher = self._publisher, None
            if old is not None:
                node.destroy_publisher(old)
            self._clock, self._state = clock, state
            if state != ServiceIntrospectionState.OFF:
                self._publisher = node.create_publisher(self._entity.srv_type.Event,
                                                        self._entity.srv_name + EVENT_SUFFIX, qos)

    def record(self, event_type: int, origin: tuple[bytes, int], *, request: Any = None,
               response: Any = None) -> None:
        """Publish one step of the call `origin` names; the request or response only with CONTENTS."""
        publisher, clock, state = self._publisher, self._clock, self._state
        if publisher is None or clock is None:
            return
        from interfaces.service_msgs.msg import ServiceEventInfo
        gid, sequence = origin
        event = self._entity.srv_type.Event()
        event.info = ServiceEventInfo(event_type=event_type, stamp=clock.now().to_msg(), client_gid=list(gid),
                                      sequence_number=sequence)
        if state == ServiceIntrospectionState.CONTENTS:
            event.request = [] if request is None else [request]
            event.response = [] if response is None else [response]
        try:
            publisher.publish(event)
        except RuntimeError:  # destroyed meanwhile (reconfigured, or the node is going)
            pass


class Introspectable:
    """What Service and Client share: `configure_introspection` and the (lazily made) recorder."""

    _introspection: ServiceIntrospection | None = None

    def configure_introspection(self, clock: Clock, service_event_qos_profile: QoSProfile,
                                introspection_state: ServiceIntrospectionState | int) -> None:
        """Publish this endpoint's service events on `<service>/_service_event` (rclpy's API).

        :param clock: The clock that stamps the events (usually the node's).
        :param service_event_qos_profile: The QoS of the event publisher.
        :param introspection_state: OFF, METADATA (events only) or CONTENTS (with the request or
            response).
        """
        if self._introspection is None:
            self._introspection = ServiceIntrospection(self)
        self._introspection.configure(clock, service_event_qos_profile, introspection_state)
