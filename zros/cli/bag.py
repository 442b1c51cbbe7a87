"""`zros bag record|play|info|convert`: ros2 bag's verbs on zros (MessagePack) and rosbag2 (CDR) bags."""
from __future__ import annotations

import argparse
import json
import sys
import threading

__all__ = ['add_arguments']


def add_arguments(parser: argparse.ArgumentParser) -> None:
    sub = parser.add_subparsers(dest='bag_verb', metavar='<command>')

    p = sub.add_parser('record', help='Record topics into a bag (an MCAP file in a directory)')
    p.add_argument('topics', nargs='*', help='Topics to record (they may appear later)')
    p.add_argument('-a', '--all', action='store_true', help='Record all topics, including ones that appear later')
    p.add_argument('--include-hidden-topics', action='store_true', help='With -a, record hidden topics too')
    p.add_argument('-o', '--output', help='Bag directory to create (default: rosbag2_YYYY_MM_DD-HH_MM_SS)')
    p.add_argument('-f', '--format', '--serialization-format', dest='format', default='cdr',
                   choices=('cdr', 'msgpack'),
                   help="Message encoding: 'cdr' (default: a rosbag2 bag that ros2 bag, Foxglove, PlotJuggler, "
                        "rosbags and mcap_ros2 read) or 'msgpack' (zros's own, payloads byte for byte, faster)")
    p.add_argument('-s', '--storage', default='mcap', choices=('mcap', 'sqlite3'),
                   help='Storage: mcap (default) or sqlite3 (.db3; not with --format msgpack)')
    p.add_argument('--max-duration', type=float, metavar='S', help='Stop recording after S seconds')
    p.set_defaults(handler=_one_line_errors(cmd_record))

    p = sub.add_parser('play', help='Play back a bag')
    p.add_argument('bag_path', help='Bag directory, .mcap or .db3 file (zros or ROS 2 recordings)')
    p.add_argument('-r', '--rate', type=float, default=1.0, help='Playback speed factor (default 1.0)')
    p.add_argument('-l', '--loop', action='store_true', help='Play the bag again and again until Ctrl-C')
    p.add_argument('--topics', nargs='+', metavar='TOPIC', help='Only play these topics')
    p.add_argument('--clock', nargs='?', type=float, const=40.0, default=None, metavar='HZ',
                   help='Publish the bag time on /clock at HZ (default 40 when given without a value)')
    p.add_argument('-d', '--delay', type=float, default=0.0, help='Seconds to wait before playing')
    p.add_argument('--start-offset', type=float, default=0.0, help='Start this many seconds into the bag')
    p.set_defaults(handler=_one_line_errors(cmd_play))

    p = sub.add_parser('info', help='Print information about a bag')
    p.add_argument('bag_path', help='Bag directory, .mcap or .db3 file')
    p.add_argument('--json', action='store_true', help='Machine-readable output')
    p.set_defaults(handler=_one_line_errors(cmd_info))

    p = sub.add_parser('convert', help='Convert a zros bag to a rosbag2 (CDR) bag or back')
    p.add_argument('input', help='Bag directory, .mcap or .db3 file to read')
    p.add_argument('output', help='Bag directory to create')
    p.add_argument('-f', '--format', '--serialization-format', dest='format', required=True,
                   choices=('msgpack', 'cdr'), help="Encoding of the new bag: 'cdr' for ROS tools, 'msgpack' for zros")
    p.add_argument('-s', '--storage', default='mcap', choices=('mcap', 'sqlite3'),
                   help='Storage of the new bag: mcap (default) or sqlite3 (with --format cdr only)')
    p.set_defaults(handler=_one_line_errors(cmd_convert))


def _one_line_errors(handler):
    """File-system and MCAP failures (disk full, a corrupt file) become one-line CliErrors."""
    def run(args: argparse.Namespace) -> int:
        from zros.errors import CliError
        try:
            return handler(args)
        except OSError as exc:
            raise CliError(f"{exc.strerror or exc}{': ' + str(exc.filename) if exc.filename else ''}") from None
        except Exception as exc:
            if type(exc).__module__.startswith('mcap'):
                raise CliError(f'cannot read the bag: {type(exc).__name__}: {exc}') from None
            raise
    return run


class _StopOnSignals:
    """SIGINT and SIGTERM call `stop()` instead of raising, so the bag is finished cleanly;
    a second signal interrupts for good."""

    def __init__(self, stop) -> None:
        self._stop = stop
        self._previous = {}
        self._count = 0

    def __enter__(self) -> '_StopOnSignals':
        import signal
        for signum in (signal.SIGINT, signal.SIGTERM):
            self._previous[signum] = signal.signal(signum, self._handle)
        return self

    def _handle(self, signum, frame) -> None:
        self._count += 1
        if self._count > 1:
            raise KeyboardInterrupt
        self._stop()

    def __exit__(self, *exc) -> None:
        import signal
        for signum, handler in self._previous.items():
            signal.signal(signum, handler)


def cmd_record(args: argparse.Namespace) -> int:
    from zros.bag.convert import open_writer
    from zros.bag.recorder import Recorder
    from zros.bag.writer import default_bag_name
    from zros.cli.common import absolute_name, cli_context
    from zros.errors import CliError
    if not args.all and not args.topics:
        raise CliError('no topics given: name the topics to record, or use -a/--all')
    if args.max_duration is not None and args.max_duration <= 0:
        raise CliError('--max-duration must be > 0')
    topics = [absolute_name(t) for t in args.topics]
    output = args.output or default_bag_name()
    stop = threading.Event()
    # Signals stop the recording from before the file exists, so a Ctrl-C at any moment still
    # leaves a finished file.
    with _StopOnSignals(stop.set), cli_context() as ctx:
        writer = open_writer(output, format=args.format, storage=args.storage)
        try:
            recorder = Recorder(ctx, writer, topics=topics, all_topics=args.all,
                                include_hidden=args.include_hidden_topics, stop_event=stop)
        except BaseException:
            writer.close()
            raise
        print(f"Recording to '{writer.path}'", file=sys.stderr, flush=True)
        recorder.run(max_duration=args.max_duration)
        print(f'Recorded {recorder.message_count} messages to {writer.path}', file=sys.stderr, flush=True)
    return 0


def cmd_play(args: argparse.Namespace) -> int:
    from zros.bag.player import Player
    from zros.cli.common import absolute_name, cli_context
    topics = [absolute_name(t) for t in args.topics] if args.topics else None
    stop = threading.Event()
    with _StopOnSignals(stop.set), cli_context() as ctx:
        player = Player(ctx, args.bag_path, rate=args.rate, loop=args.loop, topics=topics, clock_hz=args.clock,
                        delay=args.delay, start_offset=args.start_offset, stop_event=stop)
        player.run()
    if player.undecodable:
        skipped = ', '.join(f'{count} on {topic}' for topic, count in sorted(player.undecodable.items()))
        print(f'Skipped messages that did not decode: {skipped}', file=sys.stderr)
        return 1
    return 0


def cmd_convert(args: argparse.Namespace) -> int:
    from zros.bag.convert import convert
    written, skipped = convert(args.input, args.output, format=args.format, storage=args.storage,
                               log=lambda text: print(text, file=sys.stderr, flush=True))
    print(f"Converted {written} messages to '{args.output}' ({args.format}, {args.storage})")
    if skipped:
        print(f'Skipped {skipped} messages that did not decode', file=sys.stderr)
        return 1
    return 0


def _size(num: int) -> str:
    value = float(num)
    for unit in ('B', 'KiB', 'MiB', 'GiB'):
        if value < 1024 or unit == 'GiB':
            return f'{value:.0f} {unit}' if unit == 'B' else f'{value:.1f} {unit}'
        value /= 1024
    return f'{num} B'


def _stamp(ns: int) -> str:
    import time
    sec, nsec = divmod(ns, 1_000_000_000)
    return f"{time.strftime('%b %d %Y %H:%M:%S', time.localtime(sec))}.{nsec:09d} ({sec}.{nsec:09d})"


def cmd_info(args: argparse.Namespace) -> int:
    from zros.bag.reader import open_bag
    summary = open_bag(args.bag_path).summary()
    duration = summary.end - summary.start
    if args.json:
        print(json.dumps({'files': summary.files, 'size': summary.size, 'storage_id': summary.storage_id,
                          'duration_ns': duration, 'start_ns': summary.start, 'end_ns': summary.end,
                          'message_count': summary.message_count, 'complete': summary.complete,
                          'topics': [t._asdict() for t in summary.topics]}))
        return 0
    label = '{:<19}'.format
    print()
    print(f"{label('Files:')}{', '.join(summary.files)}")
    print(f"{label('Bag size:')}{_size(summary.size)}")
    print(f"{label('Storage id:')}{summary.storage_id}")
    print(f"{label('ROS Distro:')}zros")
    print(f"{label('Duration:')}{duration // 1_000_000_000}.{duration % 1_000_000_000:09d}s")
    print(f"{label('Start:')}{_stamp(summary.start)}")
    print(f"{label('End:')}{_stamp(summary.end)}")
    print(f"{label('Messages:')}{summary.message_count}")
    width = max((len(t.name) for t in summary.topics), default=0)
    type_width = max((len(t.type) for t in summary.topics), default=0)
    count_width = max((len(str(t.count)) for t in summary.topics), default=0)
    for i, t in enumerate(summary.topics):
        print(f"{label('Topic information:' if i == 0 else '')}Topic: {t.name:<{width}} | "
              f"Type: {t.type:<{type_width}} | Count: {t.count:<{count_width}} | Serialization Format: {t.encoding}")
    if not summary.topics:
        print(label('Topic information:'))
    if not summary.complete:
        print(f"{label('Note:')}the file has no summary (its recorder was killed); figures come from a scan")
    return 0
