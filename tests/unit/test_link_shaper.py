"""tools/link_shaper.py's timing: when a chunk offered at time t reaches the other end of the link.

No sockets: the model (token bucket, outages, loss bursts, one direction's schedule) is pure, and
the proxy only sleeps until the times it computes.
"""
from __future__ import annotations

import random

import pytest

from tools.link_shaper import AnyOutage, Direction, Link, LinkSettings, Outages, TokenBucket, _forward, stall_schedule


def direction(**settings) -> Direction:
    return Direction(LinkSettings(**settings), Outages(), random.Random(1))


def test_latency_alone_delays_every_chunk_by_it():
    d = direction(latency=0.03)
    assert d.schedule(10.0, 100) == pytest.approx(10.03)
    assert d.schedule(10.5, 100) == pytest.approx(10.53)


def test_jitter_stays_within_its_bounds_and_never_reorders():
    d = direction(latency=0.03, jitter=0.005)
    times = [0.001 * i for i in range(2000)]
    delivered = [d.schedule(t, 10) for t in times]
    delays = [out - t for out, t in zip(delivered, times)]
    assert all(0.025 - 1e-9 <= x for x in delays)
    assert max(delays) <= 0.035 + 0.001          # at most one chunk's wait behind a slower one
    assert delivered == sorted(delivered)          # TCP: bytes arrive in the order they were sent
    spaced = [direction(latency=0.03, jitter=0.005).schedule(0.0, 10) for _ in range(1)]
    assert 0.025 <= spaced[0] <= 0.035


def test_token_bucket_lets_a_burst_through_then_paces_at_the_rate():
    bucket = TokenBucket(LinkSettings(rate=8000.0, burst=1000))   # 1000 bytes/s
    assert bucket.take(0.0, 1000) == 0.0          # the burst leaves at once
    assert bucket.take(0.0, 500) == pytest.approx(0.5)
    assert bucket.take(0.0, 500) == pytest.approx(1.0)   # back to back: one after the other
    assert bucket.take(3.0, 200) == 3.0           # refilled while idle


def test_token_bucket_refill_is_capped_at_the_burst():
    bucket = TokenBucket(LinkSettings(rate=8000.0, burst=1000))
    bucket.take(0.0, 1000)
    assert bucket.take(100.0, 1000) == 100.0      # a long idle time saves no more than the burst
    assert bucket.take(100.0, 1000) == pytest.approx(101.0)


def test_bandwidth_cap_bounds_the_throughput_of_a_stream():
    d = direction(rate=2e6, burst=16384)
    last = 0.0
    for i in range(1000):                          # 4 MB offered in 0.1 s
        last = d.schedule(i * 1e-4, 4096)
    assert last == pytest.approx((4096 * 1000 - 16384) * 8 / 2e6, rel=1e-3)


def test_no_rate_means_no_cap():
    assert TokenBucket(LinkSettings()).take(5.0, 10 ** 9) == 5.0


def test_outages_merge_and_say_when_the_link_is_back():
    outages = Outages()
    outages.add(10.0, 5.0)
    outages.add(14.0, 2.0)                         # overlaps: one outage 10..16
    outages.add(30.0, 1.0)
    assert outages.up_at(9.0) == 9.0
    assert outages.up_at(10.0) == 16.0 and outages.up_at(15.9) == 16.0
    assert outages.up_at(16.0) == 16.0
    assert outages.down(30.5) and not outages.down(31.0)
    outages.forget_before(20.0)
    assert outages.up_at(12.0) == 12.0 and outages.up_at(30.2) == 31.0


def test_a_drop_out_holds_what_is_sent_during_it_and_in_flight():
    link = Link(LinkSettings(latency=0.03))
    link.drops.add(1.0, 5.0)
    assert link.up.schedule(0.99, 100) == pytest.approx(6.0)   # in flight when the link went: held
    assert link.down.schedule(2.0, 100) == pytest.approx(6.03)  # sent during it: leaves at the end
    assert link.up.schedule(7.0, 100) == pytest.approx(7.03)


def test_loss_bursts_are_a_poisson_process_of_the_given_rate():
    bursts = stall_schedule(random.Random(3), rate=2.0, seconds=0.2, start=100.0, horizon=500.0)
    assert all(100.0 <= s < 600.0 and d == 0.2 for s, d in bursts)
    assert all(b[0] >= a[0] + a[1] for a, b in zip(bursts, bursts[1:]))   # never overlapping
    # rate 2/s counted on the link's up time (each burst takes 0.2 s): about 500 / (0.5 + 0.2)
    assert 600 < len(bursts) < 830
    assert stall_schedule(random.Random(3), 0.0, 0.2, 0.0, 100.0) == []


def test_link_plans_stalls_ahead_and_both_directions_feel_them():
    link = Link(LinkSettings(stall_rate=1.0, stall=0.5), seed=7)
    link.plan_stalls(0.0, horizon=100.0)
    down = [t / 10 for t in range(1000) if link.outages.down(t / 10)]
    assert 100 < len(down) < 500                   # about a third of the time at 1 burst/s of 0.5 s
    t = down[0]
    assert link.up.schedule(t, 10) > t and link.down.schedule(t, 10) > t


def test_settings_refuse_unknown_names_and_bad_values():
    s = LinkSettings()
    s.update({'latency': 0.05, 'burst': 2048.0, 'dropout_mode': 'reset'})
    assert (s.latency, s.burst, s.dropout_mode) == (0.05, 2048, 'reset')
    for bad in ({'latnecy': 1}, {'rate': -1}, {'jitter': 'x'}, {'dropout_mode': 'cut'}):
        with pytest.raises(ValueError):
            s.update(bad)


def test_forward_argument_shape():
    assert _forward('10.0.0.1:7447=10.0.0.2:7448') == (('10.0.0.1', 7447), ('10.0.0.2', 7448))
    with pytest.raises(Exception, match='LISTEN_HOST:PORT=TARGET_HOST:PORT'):
        _forward('10.0.0.1:7447')


def test_drop_outs_and_loss_bursts_add_up_and_replanning_keeps_the_drop_out():
    link = Link(LinkSettings(stall_rate=1.0, stall=0.5), seed=2)
    link.plan_stalls(0.0, horizon=100.0)
    link.drops.add(10.0, 5.0)
    assert link.outages.up_at(12.0) >= 15.0          # the drop-out, and any burst right after it
    link.settings.update({'stall_rate': 0.0})
    link.replan_stalls(12.0)                         # during the drop-out...
    link.plan_stalls(12.0)
    assert link.outages.up_at(12.0) == 15.0          # ...which runs on, but no burst follows it
    assert not any(link.outages.down(15.0 + t / 10) for t in range(700))


def test_any_outage_chains_overlapping_parts():
    a, b = Outages(), Outages()
    a.add(0.0, 1.0)
    b.add(0.9, 1.0)                                  # starts before a ends, ends after it
    a.add(1.8, 1.0)
    assert AnyOutage(a, b).up_at(0.5) == pytest.approx(2.8)
    assert AnyOutage(a, b).up_at(3.0) == 3.0
    b.forget_after(0.5)
    assert AnyOutage(a, b).up_at(0.5) == 1.0
