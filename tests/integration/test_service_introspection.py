"""Service introspection: a configured service and client publish the four steps of each call
on `<service>/_service_event`, matched by the client's gid and the request's sequence number."""
from __future__ import annotations

from zros.executors import SingleThreadedExecutor
from zros.node import Node
from zros.qos import QoSProfile
from zros.service_introspection import ServiceIntrospectionState


def test_four_events_per_call_with_contents_then_metadata_then_none(context, spin_for):
    from interfaces.service_msgs.msg import ServiceEventInfo
    from interfaces.std_srvs.srv import SetBool
    node = Node('introspected', context=context)
    events = []
    node.create_subscription(SetBool.Event, 'flip/_service_event', events.append, 10)
    service = node.create_service(SetBool, 'flip', lambda req, resp: SetBool.Response(success=not req.data))
    client = node.create_client(SetBool, 'flip')
    for entity in (service, client):
        entity.configure_introspection(node.get_clock(), QoSProfile(depth=10), ServiceIntrospectionState.CONTENTS)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    assert client.wait_for_service(5.0)

    def call_and_collect(count: int) -> dict:
        events.clear()
        future = client.call_async(SetBool.Request(data=True))
        spin_for(executor, lambda: future.done() and len(events) >= count, message=f'{count} service events')
        return {event.info.event_type: event for event in events}

    steps = call_and_collect(4)
    assert set(steps) == {ServiceEventInfo.REQUEST_SENT, ServiceEventInfo.REQUEST_RECEIVED,
                          ServiceEventInfo.RESPONSE_SENT, ServiceEventInfo.RESPONSE_RECEIVED}
    assert len({(bytes(e.info.client_gid), e.info.sequence_number) for e in steps.values()}) == 1
    assert steps[ServiceEventInfo.REQUEST_RECEIVED].request[0].data is True
    assert steps[ServiceEventInfo.RESPONSE_RECEIVED].response[0].success is False
    assert not steps[ServiceEventInfo.RESPONSE_SENT].request

    for entity in (service, client):
        entity.configure_introspection(node.get_clock(), QoSProfile(depth=10), ServiceIntrospectionState.METADATA)
    steps = call_and_collect(4)
    assert all(not e.request and not e.response for e in steps.values())

    client.configure_introspection(node.get_clock(), QoSProfile(depth=10), ServiceIntrospectionState.OFF)
    steps = call_and_collect(2)        # the service's two steps only
    assert set(steps) == {ServiceEventInfo.REQUEST_RECEIVED, ServiceEventInfo.RESPONSE_SENT}
