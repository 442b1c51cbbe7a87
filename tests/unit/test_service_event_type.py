"""Every service type has an Event message (what introspection publishes), as rosidl makes one."""
from __future__ import annotations

from zros.message import deserialize, serialize
from zros.typesupport import get_service, get_type


def test_the_event_holds_info_and_at_most_one_request_and_response():
    SetBool = get_service('std_srvs/srv/SetBool')
    Event = SetBool.Event
    assert Event._TYPE == 'std_srvs/srv/SetBool_Event' and get_type('std_srvs/srv/SetBool_Event') is Event
    assert Event._FIELD_TYPES == {'info': 'service_msgs/ServiceEventInfo', 'request': 'std_srvs/SetBool_Request[<=1]',
                                  'response': 'std_srvs/SetBool_Response[<=1]'}
    event = Event(request=[SetBool.Request(data=True)])
    event.info.sequence_number = 7
    event.info.client_gid = list(range(16))
    back = deserialize(serialize(event), Event)
    assert back.request[0].data is True and back.response == [] and back.info.sequence_number == 7
    assert list(back.info.client_gid) == list(range(16))
