"""zros.wire's attachment as a writer stamps it and a reader reads it (protocol v2): the
layout other zros processes, the bridges and bag recording rely on."""
from __future__ import annotations

import time

from zros.wire import GID_AT, MAGIC, TYPE_AT, AttachmentWriter, read_header, type_tail

from interfaces.geometry_msgs.msg import Twist
from interfaces.std_msgs.msg import String


def test_a_writer_stamps_its_gid_a_sequence_from_one_the_time_and_the_type():
    writer = AttachmentWriter(Twist)
    before = time.time_ns()
    stamps = [writer.next() for _ in range(3)]
    after = time.time_ns()
    headers = [read_header(stamp) for stamp in stamps]
    assert all(stamp[:GID_AT] == MAGIC for stamp in stamps)
    assert [h[1] for h in headers] == [1, 2, 3]
    assert len({h[0] for h in headers}) == 1 and len(headers[0][0]) == 16
    assert all(before <= h[2] <= after for h in headers)
    assert all(h[3] == type_tail(Twist) == stamp[TYPE_AT:] for h, stamp in zip(headers, stamps))


def test_writers_have_their_own_gid_and_sequence():
    one, two = AttachmentWriter(String), AttachmentWriter(String)
    one.next()
    first_of_two = read_header(two.next())
    assert first_of_two[1] == 1
    assert first_of_two[0] != read_header(one.next())[0]
