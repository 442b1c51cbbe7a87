"""The frame tree and its time-stamped history: tf2's BufferCore, without any transport.

Each child frame keeps the samples received for it over the last `cache_time` (default 10 s):
stamps in order, with the parent and the transform of each. A lookup at time t walks from the
source frame up to the root and from the target frame up to the first frame both walks share,
interpolating every link at t (translation linearly, rotation by slerp) and composing. Time
zero means "the latest time at which every link of the chain is known". Static frames hold one
transform, valid at every time.

Thread safety: one lock guards the tree, so a Zenoh thread may insert while executor threads
look up. Times inside are integer nanoseconds; the public methods take zros.time.Time or a
builtin_interfaces/msg/Time.
"""
from __future__ import annotations

import bisect
import math
import threading
import time as _time
from typing import Any, Iterable

from zros.logging import get_logger
from zros.tf2_ros.exceptions import (ConnectivityException, ExtrapolationException, InvalidArgumentException,
                                     LookupException, TransformException)
from zros.tf2_ros.transform_math import (IDENTITY, QUATERNION_TOLERANCE, Transform, compose, interpolate, inverse,
                                         normalize_quaternion)

__all__ = ['BufferCore', 'DEFAULT_CACHE_TIME_NS', 'stamp_nanoseconds', 'display_time']

#: tf2's BUFFER_CORE_DEFAULT_CACHE_TIME.
DEFAULT_CACHE_TIME_NS = 10_000_000_000
#: Deeper than this, the tree must contain a loop.
_MAX_GRAPH_DEPTH = 1000
#: Two writers of one frame that take turns within this many seconds are fighting over it.
_FIGHT_WINDOW_S = 1.0

_logger = get_logger('tf2_buffer')


def stamp_nanoseconds(stamp: Any) -> int:
    """Nanoseconds of a zros.time.Time, a builtin_interfaces/msg/Time or None (zero)."""
    if stamp is None:
        return 0
    ns = getattr(stamp, 'nanoseconds', None)
    if ns is not None:
        return ns
    try:
        return stamp.sec * 1_000_000_000 + stamp.nanosec
    except AttributeError:
        raise TypeError(f'expected a zros.time.Time or a builtin_interfaces/msg/Time, got '
                        f'{type(stamp).__name__}') from None


def display_time(ns: int) -> str:
    """tf2's displayTimePoint: seconds with six decimals."""
    return f'{ns / 1e9:.6f}'


class _Cache:
    """The history of one child frame. `static` caches hold exactly one sample at stamp 0."""

    __slots__ = ('stamps', 'parents', 'values', 'static', 'authority', 'writer', 'writer_wall', 'switches',
                 'fight_warned')

    def __init__(self, static: bool) -> None:
        self.stamps: list[int] = []
        self.parents: list[str] = []
        self.values: list[Transform] = []
        self.static = static
        self.authority = ''
        self.writer: Any = None
        self.writer_wall = 0.0
        self.switches = 0
        self.fight_warned = False

    def insert(self, stamp: int, parent: str, value: Transform, max_age: int) -> bool:
        """Store a sample; False when it is older than the cache keeps (tf2's TF_OLD_DATA)."""
        if self.static:
            self.stamps, self.parents, self.values = [0], [parent], [value]
            return True
        stamps = self.stamps
        if not stamps or stamp > stamps[-1]:
            stamps.append(stamp)
            self.parents.append(parent)
            self.values.append(value)
            oldest_kept = stamp - max_age
            if stamps[0] < oldest_kept:
                cut = bisect.bisect_left(stamps, oldest_kept)
                del stamps[:cut], self.parents[:cut], self.values[:cut]
            return True
        if stamp < stamps[-1] - max_age:
            return False
        i = bisect.bisect_left(stamps, stamp)
        if stamps[i] == stamp:  # repeated stamp: tf2 keeps the first and ignores the rest
            return True
        stamps.insert(i, stamp)
        self.parents.insert(i, parent)
        self.values.insert(i, value)
        return True

    def latest(self) -> tuple[int, str]:
        """(latest stamp, its parent); static frames report stamp 0 (valid at any time)."""
        return self.stamps[-1], self.parents[-1]

    def sample(self, t: int) -> tuple[str, Transform]:
        """(parent, transform) at time t (0 = latest); ExtrapolationException outside the data."""
        stamps = self.stamps
        if self.static or t == 0:
            return self.parents[-1], self.values[-1]
        if len(stamps) == 1:
            if stamps[0] == t:
                return self.parents[0], self.values[0]
            raise ExtrapolationException(
                f'Lookup would require extrapolation at time {display_time(t)}, but only time '
                f'{display_time(stamps[0])} is in the buffer')
        if t > stamps[-1]:
            raise ExtrapolationException(
                f'Lookup would require extrapolation into the future.  Requested time {display_time(t)} '
                f'but the latest data is at time {display_time(stamps[-1])}')
        i = bisect.bisect_left(stamps, t)
        if stamps[i] == t:
            return self.parents[i], self.values[i]
        if i == 0:
            raise ExtrapolationException(
                f'Lookup would require extrapolation into the past.  Requested time {display_time(t)} '
                f'but the earliest data is at time {display_time(stamps[0])}')
        parent = self.parents[i - 1]
        if self.parents[i] != parent:  # re-parented between the two samples: no interpolation
            return parent, self.values[i - 1]
        t0 = stamps[i - 1]
        return parent, interpolate(self.values[i - 1], self.values[i], (t - t0) / (stamps[i] - t0))


class BufferCore:
    """tf2_py's BufferCore: frames and transforms in time, looked up by name."""

    def __init__(self, cache_time: Any = None) -> None:
        self._cache_ns = DEFAULT_CACHE_TIME_NS if cache_time is None else int(cache_time.nanoseconds)
        self._lock = threading.RLock()
        self._caches: dict[str, _Cache] = {}
        self._parents_seen: set[str] = set()   # frames that only ever appear as parents
        self._warned: set[tuple[str, str]] = set()

    # -- filling -----------------------------------------------------------------------------
    def set_transform(self, transform: Any, authority: str) -> None:
        """Add a geometry_msgs/TransformStamped to the history (a refused one is logged once and
        left out; tf2_py returns nothing either way)."""
        self._set_msg(transform, authority, False)

    def set_transform_static(self, transform: Any, authority: str) -> None:
        """Add a transform that holds at every time (what /tf_static carries)."""
        self._set_msg(transform, authority, True)

    def _set_msg(self, msg: Any, authority: str, static: bool) -> bool:
        tr, rot = msg.transform.translation, msg.transform.rotation
        stamp = msg.header.stamp
        try:
            inserted = self._insert(msg.child_frame_id, msg.header.frame_id, stamp.sec * 1_000_000_000 + stamp.nanosec,
                                    (tr.x, tr.y, tr.z, rot.x, rot.y, rot.z, rot.w), authority, static, authority)
        except InvalidArgumentException:
            inserted = False
        if inserted:
            self._on_new_data()
        return inserted

    def _insert_many(self, items: Iterable[tuple[str, str, int, Transform]], authority: str, static: bool,
                     writer: Any) -> None:
        """Insert (child, parent, stamp ns, transform) samples from one message of `writer`."""
        inserted = False
        for child, parent, stamp, value in items:
            try:
                inserted |= self._insert(child, parent, stamp, value, authority, static, writer)
            except InvalidArgumentException:
                pass  # already logged once
        if inserted:
            self._on_new_data()

    def _insert(self, child: str, parent: str, stamp: int, value: Transform, authority: str, static: bool,
                writer: Any) -> bool:
        child, parent = child.lstrip('/'), parent.lstrip('/')
        problem = None
        if not child:
            problem = 'child_frame_id is empty'
        elif not parent:
            problem = 'frame_id is empty'
        elif child == parent:
            problem = f'frame_id and child_frame_id are both "{child}"'
        elif not all(math.isfinite(v) for v in value):
            problem = f'it contains a NaN or infinite value {value}'
        if problem is None:
            try:
                quat, n2 = normalize_quaternion(*value[3:])
            except ValueError as exc:
                problem = str(exc)
            else:
                if abs(n2 - 1.0) > QUATERNION_TOLERANCE:
                    self._warn_once(('denormalized', child),
                                    f'TF_DENORMALIZED_QUATERNION: normalising the rotation of frame "{child}" '
                                    f'from authority "{authority}": quaternion {value[3:]} has norm '
                                    f'{math.sqrt(n2):.6f} (warned once per frame)')
                value = value[:3] + quat
        if problem is not None:
            text = f'Ignoring transform for child_frame_id "{child}" from authority "{authority}": {problem}'
            self._warn_once(('invalid', child, problem), text, error=True)
            raise InvalidArgumentException(text)
        with self._lock:
            cache = self._caches.get(child)
            if cache is None or cache.static != static:
                cache = self._caches[child] = _Cache(static)
                self._parents_seen.discard(child)
            if parent not in self._caches:
                self._parents_seen.add(parent)
            if not cache.insert(stamp, parent, value, self._cache_ns):
                self._warn_once(('old', child),
                                f'TF_OLD_DATA ignoring data from the past for frame {child} at time '
                                f'{display_time(stamp)} according to authority {authority} (older than the '
                                f'{self._cache_ns / 1e9:g} s the buffer keeps; warned once per frame)')
                return False
            self._note_writer(cache, child, parent, writer)
            cache.authority = authority
        return True

    def _note_writer(self, cache: _Cache, child: str, parent: str, writer: Any) -> None:
        """Warn once when two writers take turns publishing one frame (they fight over it)."""
        now = _time.monotonic()
        if writer != cache.writer:
            if cache.writer is not None and now - cache.writer_wall < _FIGHT_WINDOW_S:
                cache.switches += 1
                if cache.switches >= 2 and not cache.fight_warned and not cache.static:
                    cache.fight_warned = True
                    parents = sorted(set(cache.parents[-20:]) | {parent})
                    _logger.warn(f'frame "{child}" is being published by more than one broadcaster'
                                 f' (parent{"s" if len(parents) > 1 else ""} {", ".join(parents)}); '
                                 'lookups will jump between them')
            cache.writer = writer
        cache.writer_wall = now

    def _warn_once(self, key: tuple, text: str, error: bool = False) -> None:
        if key in self._warned:
            return
        self._warned.add(key)
        (_logger.error if error else _logger.warn)(text)

    def _on_new_data(self) -> None:
        """Hook for subclasses (Buffer wakes its waiters)."""

    def clear(self) -> None:
        """Forget every dynamic transform (e.g. after simulated time jumped back: a
        /reset_simulation). Static transforms stay, as tf2's clear() keeps its static caches:
        /tf_static is latched and sent once, so nothing would bring them back."""
        with self._lock:
            self._caches = {child: cache for child, cache in self._caches.items() if cache.static}
            self._parents_seen = {parent for parent in self._parents_seen if parent not in self._caches}
            self._parents_seen.update(cache.parents[-1] for cache in self._caches.values()
                                      if cache.parents[-1] not in self._caches)

    # -- lookups -----------------------------------------------------------------------------
    def lookup_transform_core(self, target_frame: str, source_frame: str, time: Any) -> Any:
        """geometry_msgs/TransformStamped mapping data in `source_frame` into `target_frame`."""
        stamp, value = self._lookup(target_frame, source_frame, stamp_nanoseconds(time))
        return _stamped(target_frame, source_frame, stamp, value)

    def lookup_transform_full_core(self, target_frame: str, target_time: Any, source_frame: str,
                                   source_time: Any, fixed_frame: str) -> Any:
        """Source at source_time into the fixed frame, then the fixed frame into target at
        target_time ("time travel" through a frame that does not move)."""
        _, source_in_fixed = self._lookup(fixed_frame, source_frame, stamp_nanoseconds(source_time))
        stamp, fixed_in_target = self._lookup(target_frame, fixed_frame, stamp_nanoseconds(target_time))
        return _stamped(target_frame, source_frame, stamp, compose(fixed_in_target, source_in_fixed))

    def can_transform_core(self, target_frame: str, source_frame: str, time: Any) -> tuple[bool, str]:
        """(True, '') when lookup_transform_core would succeed, else (False, the reason)."""
        try:
            self._lookup(target_frame, source_frame, stamp_nanoseconds(time))
        except TransformException as exc:
            return False, str(exc)
        return True, ''

    def can_transform_full_core(self, target_frame: str, target_time: Any, source_frame: str,
                                source_time: Any, fixed_frame: str) -> tuple[bool, str]:
        """Tell, without waiting, whether a transform between two times can be looked up.

        :param target_frame: The frame to express data in.
        :param target_time: The time of the target frame.
        :param source_frame: The frame the data is in.
        :param source_time: The time of the source data.
        :param fixed_frame: A frame that does not move between the two times.
        :return: ``(True, '')``, or ``(False, reason)`` with tf2's error text.
        """
        try:
            self.lookup_transform_full_core(target_frame, target_time, source_frame, source_time, fixed_frame)
        except TransformException as exc:
            return False, str(exc)
        return True, ''

    def _lookup(self, target: str, source: str, t: int) -> tuple[int, Transform]:
        """(stamp used, transform of source in target) at time t ns (0 = latest common)."""
        with self._lock:
            self._validate(target, 'target_frame')
            self._validate(source, 'source_frame')
            caches = self._caches
            if source == target:
                cache = caches.get(source)
                return (t if t or cache is None else cache.latest()[0]), IDENTITY
            if t == 0:
                t = self._latest_common_time(target, source)
            # Walk up from the source, remembering where the source is in each frame passed.
            chain = {source: IDENTITY}
            acc = IDENTITY
            frame = source
            broken: ExtrapolationException | None = None
            while frame != target:
                cache = caches.get(frame)
                if cache is None:
                    break
                try:
                    parent, value = cache.sample(t)
                except ExtrapolationException as exc:
                    broken = exc
                    break
                acc = value if acc is IDENTITY else compose(value, acc)
                frame = parent
                if frame in chain:
                    raise LookupException(f'The tf tree is invalid because it contains a loop at "{frame}".')
                chain[frame] = acc
            if frame == target:
                return t, acc
            # Walk up from the target until a frame of the source's walk.
            acc_t = IDENTITY
            frame = target
            depth = 0
            while frame not in chain:
                cache = caches.get(frame)
                if cache is None:
                    if broken is not None:
                        raise ExtrapolationException(f'{broken}, when looking up transform from frame '
                                                     f'[{source}] to frame [{target}]')
                    raise ConnectivityException(
                        f"Could not find a connection between '{target}' and '{source}' because they are "
                        'not part of the same tree.Tf has two or more unconnected trees.')
                try:
                    parent, value = cache.sample(t)
                except ExtrapolationException as exc:
                    raise ExtrapolationException(f'{exc}, when looking up transform from frame [{source}] '
                                                 f'to frame [{target}]') from None
                acc_t = value if acc_t is IDENTITY else compose(value, acc_t)
                frame = parent
                depth += 1
                if depth > _MAX_GRAPH_DEPTH:
                    raise LookupException('The tf tree is invalid because it contains a loop.')
            source_in_common = chain[frame]
            return t, source_in_common if acc_t is IDENTITY else compose(inverse(acc_t), source_in_common)

    def _latest_common_time(self, target: str, source: str) -> int:
        """The newest time at which every dynamic link between the two frames has data (0 if
        every link is static)."""
        caches = self._caches
        times: dict[str, int] = {source: 0}   # frame -> newest common time of the links below it
        newest = 0
        frame = source
        while True:
            cache = caches.get(frame)
            if cache is None:
                break
            stamp, parent = cache.latest()
            if not cache.static:
                newest = stamp if newest == 0 else min(newest, stamp)
            frame = parent
            if frame in times:
                raise LookupException(f'The tf tree is invalid because it contains a loop at "{frame}".')
            times[frame] = newest
            if frame == target:
                return newest
        newest_t = 0
        frame = target
        depth = 0
        while frame not in times:
            cache = caches.get(frame)
            if cache is None:
                raise ConnectivityException(
                    f"Could not find a connection between '{target}' and '{source}' because they are "
                    'not part of the same tree.Tf has two or more unconnected trees.')
            stamp, parent = cache.latest()
            if not cache.static:
                newest_t = stamp if newest_t == 0 else min(newest_t, stamp)
            frame = parent
            depth += 1
            if depth > _MAX_GRAPH_DEPTH:
                raise LookupException('The tf tree is invalid because it contains a loop.')
        candidates = [x for x in (times[frame], newest_t) if x]
        return min(candidates) if candidates else 0

    def _validate(self, frame: str, argument: str) -> None:
        if not isinstance(frame, str):
            raise InvalidArgumentException(f'{argument} must be a str, got {type(frame).__name__}')
        if not frame:
            raise InvalidArgumentException(
                f'Invalid argument "" passed to lookupTransform argument {argument} - in tf2 frame_ids cannot be empty')
        if frame.startswith('/'):
            raise InvalidArgumentException(
                f'Invalid argument "{frame}" passed to lookupTransform argument {argument} - in tf2 frame_ids '
                "cannot start with a '/'")
        if frame not in self._caches and frame not in self._parents_seen:
            known = self._frame_names()
            listing = (f'Frames that exist: {", ".join(known)}.' if known
                       else 'The buffer holds no frames yet (is anything publishing /tf or /tf_static?).')
            raise LookupException(f'"{frame}" passed to lookupTransform argument {argument} does not exist. {listing}')

    # -- introspection -------------------------------------------------------------------------
    def _frame_names(self) -> list[str]:
        return sorted(set(self._caches) | self._parents_seen)

    def get_frame_strings(self) -> list[str]:
        """Every frame name known, as a sorted list."""
        with self._lock:
            return self._frame_names()

    _getFrameStrings = get_frame_strings

    def _frameExists(self, frame_id: str) -> bool:  # noqa: N802 - tf2_py's name
        with self._lock:
            return frame_id in self._caches or frame_id in self._parents_seen

    def _getParent(self, frame_id: str, time: Any) -> str:  # noqa: N802 - tf2_py's name
        with self._lock:
            cache = self._caches.get(frame_id)
            if cache is None:
                raise LookupException(f'frame "{frame_id}" has no parent')
            return cache.sample(stamp_nanoseconds(time))[0]

    def frames(self) -> dict[str, dict[str, Any]]:
        """Per child frame: parent, static, authority, number of samples, oldest and newest stamp
        (ns) and rate (samples per second of stamps): what view_frames and `zros tf` show."""
        with self._lock:
            out = {}
            for child, cache in self._caches.items():
                oldest, newest = cache.stamps[0], cache.stamps[-1]
                span = max(newest - oldest, 100_000)  # tf2 divides by at least 100 us
                out[child] = {'parent': cache.parents[-1], 'static': cache.static, 'authority': cache.authority,
                              'samples': len(cache.stamps), 'oldest': oldest, 'newest': newest,
                              'rate': 10000.0 if cache.static else len(cache.stamps) * 1e9 / span}
            return out

    def all_frames_as_yaml(self, current_time: Any = None) -> str:
        """tf2's allFramesAsYAML: one mapping per child frame (what the tf2_frames service returns)."""
        now = stamp_nanoseconds(current_time)
        frames = self.frames()
        if not frames:
            return '[]'
        lines = []
        for child, info in frames.items():
            lines += [f'{child}: ', f"  parent: '{info['parent']}'",
                      f"  broadcaster: '{info['authority'] or 'no recorded authority'}'",
                      f"  rate: {info['rate']:.3f}",
                      f"  most_recent_transform: {display_time(info['newest'])}",
                      f"  oldest_transform: {display_time(info['oldest'])}"]
            if now:
                lines.append(f"  transform_delay: {(now - info['newest']) / 1e9:.3f}")
            lines.append(f"  buffer_length: {(info['newest'] - info['oldest']) / 1e9:.3f}")
        return '\n'.join(lines) + '\n'

    def all_frames_as_string(self) -> str:
        """tf2's allFramesAsString: 'Frame X exists with parent Y.' per child frame."""
        with self._lock:
            return ''.join(f'Frame {child} exists with parent {cache.parents[-1]}.\n'
                           for child, cache in self._caches.items())


_transform_stamped: Any = None


def _stamped(target: str, source: str, stamp: int, value: Transform) -> Any:
    global _transform_stamped
    if _transform_stamped is None:
        from interfaces.geometry_msgs.msg import TransformStamped
        _transform_stamped = TransformStamped
    sec, nanosec = divmod(stamp, 1_000_000_000)
    tx, ty, tz, qx, qy, qz, qw = value
    # the message's wire header, decoded: one checked construction instead of six setter calls
    return _transform_stamped._DEC1((((sec, nanosec), target), source,
                                     ((float(tx), float(ty), float(tz)), (float(qx), float(qy), float(qz), float(qw)))))
