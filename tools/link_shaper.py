"""A bad link in user space: a TCP proxy that adds latency, jitter, a bandwidth cap and drop-outs.

The robot talks to the laptop over Wi-Fi; the tests and benchmarks/link.py need that link on one
machine, and this kernel has no netem. Zenoh runs over TCP here, so the link is shaped where TCP
would feel it: between the two ends of a TCP connection. The proxy listens on one address,
dials the real one, and passes the bytes of each direction through a `Link` model:

* **latency and jitter**: each chunk is delivered `latency +- jitter` (uniform) after it left;
  TCP never reorders bytes, so a chunk is never delivered before the one before it;
* **bandwidth**: a token bucket (`rate` bit/s, `burst` bytes) per direction;
* **loss bursts** (`stall_rate` per second, `stall` s each, at random): on TCP a lost burst of
  frames is a pause until the retransmission gets through, so it is modelled as a short outage;
* **drop-outs** of N seconds, from the control socket: nothing passes either way.

A drop-out either *holds* the connections (`dropout_mode='hold'`, the default) or *resets* them.
Holding is what Wi-Fi does: when a station loses its access point for a few seconds, nobody
sends a RST; the frames are retransmitted and TCP backs off until the radio link returns, and
the connection carries on unless an end gives up first (Zenoh's lease, 10 s by default). A
reset is what a NAT or access point that forgets the flow does; it is here to test the
reconnection path.

Nothing here imports zros: the proxy runs in its own process (in the middle network namespace
of tools/link_netns.py), and tests drive it with `control(path, cmd=...)` on its Unix socket:

    python tools/link_shaper.py --forward 10.77.1.254:7447=10.77.2.1:7447 --latency 0.03 \\
        --jitter 0.005 --rate 2e6 --control /tmp/link.sock
    python tools/link_shaper.py --control /tmp/link.sock ctl '{"cmd": "drop", "seconds": 5}'
"""
from __future__ import annotations

import argparse
import asyncio
import bisect
import collections
import contextlib
import json
import os
import random
import socket
import struct
import sys
import time
from dataclasses import dataclass, field, fields

__all__ = ['LinkSettings', 'TokenBucket', 'Outages', 'AnyOutage', 'Direction', 'Link', 'stall_schedule', 'Shaper', 'control',
           'main']

CHUNK = 4096               # [bytes] read at a time: a few frames, so a big message is paced, not sent whole
KERNEL_BUFFER = 1 << 15    # [bytes] SO_RCVBUF of the proxy's sockets (the kernel doubles it)
WINDOW = 1 << 18           # [bytes] held per direction before the proxy stops reading: about 1 s at 2 Mbit/s, an access point's queue


@dataclass
class LinkSettings:
    """What the link does; every field can be changed while it runs (`{"cmd": "set", ...}`)."""

    latency: float = 0.0        # [s] one way
    jitter: float = 0.0         # [s] +- around the latency, uniform
    rate: float = 0.0           # [bit/s] each direction; 0: no cap
    burst: int = 16384          # [bytes] the token bucket's depth
    stall_rate: float = 0.0     # [1/s] loss bursts, a Poisson process
    stall: float = 0.2          # [s] each loss burst's pause (TCP's minimum retransmission timeout)
    dropout_mode: str = 'hold'  # 'hold' (Wi-Fi) or 'reset' the connections at a drop-out

    def update(self, values: dict) -> None:
        """Set the named fields from `values`; ValueError names an unknown field or a bad value."""
        known = {f.name: f.type for f in fields(self)}
        for name, value in values.items():
            if name not in known:
                raise ValueError(f'unknown link setting {name!r} (known: {", ".join(known)})')
            if name == 'dropout_mode':
                if value not in ('hold', 'reset'):
                    raise ValueError(f"dropout_mode must be 'hold' or 'reset', got {value!r}")
            elif not isinstance(value, (int, float)) or isinstance(value, bool) or value < 0:
                raise ValueError(f'{name} must be a number >= 0, got {value!r}')
            setattr(self, name, int(value) if name == 'burst' else value)


class TokenBucket:
    """Departure times under a bandwidth cap: `burst` bytes may leave at once, then `rate` bit/s.

    The bucket goes into debt for a chunk larger than what it holds, so the chunks that follow
    wait until the link has had time to serialise it: back-to-back chunks leave at the rate.
    """

    def __init__(self, settings: LinkSettings) -> None:
        self._settings = settings
        self._tokens = float(settings.burst)
        self._last = None

    def take(self, now: float, nbytes: int) -> float:
        """The time at which `nbytes` offered at `now` have left (calls in time order)."""
        rate = self._settings.rate / 8.0
        if rate <= 0:
            return now
        if self._last is not None:
            self._tokens = min(float(self._settings.burst), self._tokens + (now - self._last) * rate)
        self._last = now
        self._tokens -= nbytes
        return now + max(0.0, -self._tokens / rate)


class Outages:
    """Intervals of wall time in which the link passes nothing, in both directions."""

    def __init__(self) -> None:
        self._starts: list[float] = []
        self._ends: list[float] = []

    def add(self, start: float, seconds: float) -> None:
        """The link is down from `start` for `seconds` (overlapping outages merge)."""
        end = start + seconds
        spans = sorted(zip(self._starts + [start], self._ends + [end]))
        merged: list[list[float]] = []
        for s, e in spans:
            if merged and s <= merged[-1][1]:
                merged[-1][1] = max(merged[-1][1], e)
            else:
                merged.append([s, e])
        self._starts = [s for s, _ in merged]
        self._ends = [e for _, e in merged]

    def clear(self) -> None:
        self._starts, self._ends = [], []

    def up_at(self, t: float) -> float:
        """The first time >= `t` at which the link is up."""
        i = bisect.bisect_right(self._starts, t) - 1
        return self._ends[i] if i >= 0 and t < self._ends[i] else t

    def down(self, t: float) -> bool:
        return self.up_at(t) > t

    def forget_before(self, t: float) -> None:
        """Drop outages that ended before `t` (a long run adds many loss bursts)."""
        keep = bisect.bisect_left(self._ends, t)
        del self._starts[:keep], self._ends[:keep]

    def forget_after(self, t: float) -> None:
        """Drop outages that start after `t` (one in progress runs on)."""
        keep = bisect.bisect_right(self._starts, t)
        del self._starts[keep:], self._ends[keep:]


class AnyOutage:
    """The link is down while any of `parts` is (drop-outs and loss bursts are kept apart, so
    that new loss settings re-plan the bursts without ending a drop-out)."""

    def __init__(self, *parts: Outages) -> None:
        self._parts = parts

    def up_at(self, t: float) -> float:
        while True:
            later = t
            for part in self._parts:
                later = part.up_at(later)
            if later == t:
                return t
            t = later

    def down(self, t: float) -> bool:
        return self.up_at(t) > t


def stall_schedule(rng: random.Random, rate: float, seconds: float, start: float, horizon: float
                   ) -> list[tuple[float, float]]:
    """Loss bursts as (start, seconds) over [start, start + horizon): a Poisson process of `rate`."""
    bursts: list[tuple[float, float]] = []
    if rate <= 0 or seconds <= 0:
        return bursts
    t = start + rng.expovariate(rate)
    while t < start + horizon:
        bursts.append((t, seconds))
        t += seconds + rng.expovariate(rate)
    return bursts


class Direction:
    """One direction of the link: when does a chunk offered now reach the other end?"""

    def __init__(self, settings: LinkSettings, outages: Outages | AnyOutage, rng: random.Random) -> None:
        self._settings = settings
        self._outages = outages
        self._rng = rng
        self._bucket = TokenBucket(settings)
        self._last_delivery = 0.0
        self.bytes = 0

    def schedule(self, now: float, nbytes: int) -> float:
        """The delivery time of `nbytes` read from the sender at `now` (calls in time order)."""
        s = self._settings
        sent = self._outages.up_at(self._bucket.take(self._outages.up_at(now), nbytes))
        delay = max(0.0, s.latency + (self._rng.uniform(-s.jitter, s.jitter) if s.jitter > 0 else 0.0))
        self._last_delivery = self._outages.up_at(max(self._last_delivery, sent + delay))
        self.bytes += nbytes
        return self._last_delivery


@dataclass
class Link:
    """Both directions and what they share: the settings and the outages (the radio is one)."""

    settings: LinkSettings = field(default_factory=LinkSettings)
    seed: int = 0

    def __post_init__(self) -> None:
        self.drops = Outages()       # from the control socket
        self.stalls = Outages()      # loss bursts, planned ahead at random
        self.outages = AnyOutage(self.drops, self.stalls)
        self._rng = random.Random(self.seed)
        self.up = Direction(self.settings, self.outages, self._rng)      # the dialling side -> target
        self.down = Direction(self.settings, self.outages, self._rng)    # target -> the dialling side
        self._stalls_until = 0.0

    def plan_stalls(self, now: float, horizon: float = 60.0) -> None:
        """Keep random loss bursts scheduled `horizon` s ahead of `now`."""
        if now + horizon <= self._stalls_until:
            return
        begin = max(now, self._stalls_until)
        for start, seconds in stall_schedule(self._rng, self.settings.stall_rate, self.settings.stall, begin,
                                             now + horizon - begin):
            self.stalls.add(start, seconds)
        self._stalls_until = now + horizon
        self.stalls.forget_before(now - 1.0)
        self.drops.forget_before(now - 1.0)

    def replan_stalls(self, now: float) -> None:
        """The loss settings changed: forget the bursts planned after `now`."""
        self.stalls.forget_after(now)
        self._stalls_until = now


# -- the proxy ---------------------------------------------------------------------------------
class _Pipe:
    """Bytes of one direction of one connection: read, scheduled, written at their time."""

    def __init__(self, direction: Direction, link: Link, reader: asyncio.StreamReader,
                 writer: asyncio.StreamWriter) -> None:
        self._direction, self._link = direction, link
        self._reader, self._writer = reader, writer
        self._queue: collections.deque[tuple[float, bytes]] = collections.deque()
        self._held = 0
        self._space = asyncio.Event()
        self._space.set()
        self._ready = asyncio.Event()
        self._eof = False

    async def read(self) -> None:
        loop = asyncio.get_running_loop()
        while True:
            await self._space.wait()
            data = await self._reader.read(CHUNK)
            if not data:
                break
            self._link.plan_stalls(loop.time())
            self._queue.append((self._direction.schedule(loop.time(), len(data)), data))
            self._held += len(data)
            if self._held >= WINDOW:
                self._space.clear()
            self._ready.set()
        self._eof = True
        self._ready.set()

    async def write(self) -> None:
        loop = asyncio.get_running_loop()
        while True:
            if not self._queue:
                if self._eof:
                    break
                self._ready.clear()
                await self._ready.wait()
                continue
            due, data = self._queue[0]
            # a drop-out declared after the chunk was scheduled holds it too
            due = self._link.outages.up_at(max(due, loop.time()))
            if due > loop.time():
                await asyncio.sleep(due - loop.time())
                continue
            self._queue.popleft()
            self._held -= len(data)
            if self._held < WINDOW:
                self._space.set()
            self._writer.write(data)
            await self._writer.drain()
        if self._writer.can_write_eof():
            self._writer.write_eof()


class Shaper:
    """The proxy: `forwards` maps (listen host, port) to (target host, port), all through one Link."""

    def __init__(self, link: Link, forwards: list[tuple[tuple[str, int], tuple[str, int]]]) -> None:
        self.link = link
        self._forwards = forwards
        self._servers: list[asyncio.base_events.Server] = []
        self._connections: set[asyncio.StreamWriter] = set()
        self.started = time.monotonic()

    async def start(self) -> None:
        for listen, target in self._forwards:
            server = await asyncio.start_server(lambda r, w, t=target: self._serve(r, w, t), *listen,
                                                reuse_address=True)
            self._servers.append(server)

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter, target: tuple[str, int]
                     ) -> None:
        loop = asyncio.get_running_loop()
        if self.link.outages.down(loop.time()) and self.link.settings.dropout_mode == 'reset':
            _reset(writer)
            return
        try:
            up_reader, up_writer = await asyncio.open_connection(*target)
        except OSError:
            _reset(writer)
            return
        for w in (writer, up_writer):
            sock = w.get_extra_info('socket')
            sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            # the link's queue is WINDOW, not a kernel receive buffer that autotuning grows to
            # megabytes while the proxy is not reading: that would be seconds of hidden queue
            sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, KERNEL_BUFFER)
        self._connections.update((writer, up_writer))
        pipes = (_Pipe(self.link.up, self.link, reader, up_writer), _Pipe(self.link.down, self.link, up_reader, writer))
        tasks = [asyncio.ensure_future(c) for p in pipes for c in (p.read(), p.write())]
        try:
            await asyncio.gather(*tasks)
        except (OSError, asyncio.IncompleteReadError):
            pass
        finally:
            for task in tasks:
                task.cancel()
            for w in (writer, up_writer):
                self._connections.discard(w)
                w.close()

    def drop(self, seconds: float) -> None:
        """A drop-out from now on; in 'reset' mode every connection is reset as well."""
        now = asyncio.get_running_loop().time()
        self.link.drops.add(now, seconds)
        if self.link.settings.dropout_mode == 'reset':
            for writer in list(self._connections):
                _reset(writer)

    def stats(self) -> dict:
        return {'up_bytes': self.link.up.bytes, 'down_bytes': self.link.down.bytes,
                'connections': len(self._connections) // 2, 'time': time.monotonic(),
                'down': self.link.outages.down(asyncio.get_running_loop().time())}

    def command(self, request: dict) -> dict:
        """One control request: set, drop, up (end every outage), stats."""
        cmd = request.get('cmd')
        if cmd == 'set':
            values = {k: v for k, v in request.items() if k != 'cmd'}
            self.link.settings.update(values)
            if {'stall_rate', 'stall'} & values.keys():
                self.link.replan_stalls(asyncio.get_running_loop().time())
        elif cmd == 'drop':
            seconds = request.get('seconds')
            if not isinstance(seconds, (int, float)) or seconds <= 0:
                raise ValueError(f'drop needs seconds > 0, got {seconds!r}')
            self.drop(float(seconds))
        elif cmd == 'up':
            self.link.drops.clear()
            self.link.stalls.clear()
        elif cmd != 'stats':
            raise ValueError(f'unknown command {cmd!r} (set, drop, up, stats)')
        return self.stats()

    async def serve_control(self, path: str) -> None:
        async def handle(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
            async for line in reader:
                try:
                    reply = {'ok': True, **self.command(json.loads(line))}
                except (ValueError, TypeError, AttributeError) as exc:
                    reply = {'ok': False, 'error': str(exc)}
                writer.write(json.dumps(reply).encode() + b'\n')
                await writer.drain()
            writer.close()
        if os.path.exists(path):
            os.unlink(path)
        self._servers.append(await asyncio.start_unix_server(handle, path))


def _reset(writer: asyncio.StreamWriter) -> None:
    """Close with a RST (linger 0), as a forgetful NAT does, rather than a clean FIN."""
    sock = writer.get_extra_info('socket')
    if sock is not None:
        try:
            sock.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack('ii', 1, 0))
        except OSError:
            pass
    writer.transport.abort()


def control(path: str, timeout: float = 5.0, **request: object) -> dict:
    """Send one request to a running shaper's control socket; its reply (RuntimeError if refused)."""
    with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as sock:
        sock.settimeout(timeout)
        sock.connect(path)
        sock.sendall(json.dumps(request).encode() + b'\n')
        data = b''
        while not data.endswith(b'\n'):
            part = sock.recv(65536)
            if not part:
                break
            data += part
    reply = json.loads(data)
    if not reply.get('ok'):
        raise RuntimeError(reply.get('error', 'refused'))
    return reply


def _forward(text: str) -> tuple[tuple[str, int], tuple[str, int]]:
    try:
        listen, target = text.split('=')
        (lh, lp), (th, tp) = (s.rsplit(':', 1) for s in (listen, target))
        return (lh, int(lp)), (th, int(tp))
    except ValueError:
        raise argparse.ArgumentTypeError(f'{text!r} is not LISTEN_HOST:PORT=TARGET_HOST:PORT') from None


async def _run(shaper: Shaper, control_path: str | None) -> None:
    await shaper.start()
    if control_path:
        await shaper.serve_control(control_path)
    print('shaping', flush=True)
    await asyncio.Event().wait()


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--forward', type=_forward, action='append', default=[],
                        help='LISTEN_HOST:PORT=TARGET_HOST:PORT (repeatable)')
    parser.add_argument('--control', help='Unix socket for control requests')
    parser.add_argument('--seed', type=int, default=0)
    for f in fields(LinkSettings):
        parser.add_argument('--' + f.name.replace('_', '-'), dest=f.name, default=f.default,
                            type=str if f.name == 'dropout_mode' else float)
    parser.add_argument('request', nargs='*', help="ctl JSON: send one request to --control and print the reply")
    args = parser.parse_args(argv)
    if args.request:
        if args.request[0] != 'ctl' or len(args.request) != 2 or not args.control:
            parser.error("give --control SOCKET ctl '{\"cmd\": ...}'")
        try:
            request = json.loads(args.request[1])
        except ValueError as exc:
            parser.exit(1, f'link_shaper: the request is not JSON ({exc}): {args.request[1]!r}\n')
        try:
            print(json.dumps(control(args.control, **request)))
        except (OSError, ValueError, RuntimeError, TypeError) as exc:
            print(f'link_shaper: {exc}', file=sys.stderr)
            return 1
        return 0
    if not args.forward:
        parser.error('give at least one --forward')
    settings = LinkSettings()
    try:
        settings.update({f.name: getattr(args, f.name) for f in fields(LinkSettings)})
    except ValueError as exc:
        parser.error(str(exc))
    shaper = Shaper(Link(settings, args.seed), args.forward)
    with contextlib.suppress(KeyboardInterrupt):
        try:
            asyncio.run(_run(shaper, args.control))
        except OSError as exc:           # the address is taken, or not in this namespace
            parser.exit(1, f'link_shaper: {exc}\n')
    return 0


if __name__ == '__main__':
    sys.exit(main())
