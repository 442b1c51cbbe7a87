"""`zros run PKG EXECUTABLE [args...]`: find an executable and run it in this process.

Executables are looked up in the package index (zros.ament_index_python.executables says in
which order: `zros.nodes` entry points, a ROS package's console scripts and `lib/PKG/` files,
then `EXECUTABLE.py` in the package's folder on `ZROS_NODE_PATH` or shipped with zros).
Every executable is loaded with zros.import_hook installed, so unmodified rclpy code runs as it is.
The module's `main()` is called with sys.argv set to [EXECUTABLE, args...], the way
ros2 run's executables see their arguments (`--ros-args` included).

Session options go before the package: `zros run --connect tcp/10.0.0.1:7447 demo_nodes talker`
(also --listen, --discovery, --domain-id, --zenoh-config). They set the ZROS_* environment
variables before the executable starts (see docs/multi-machine.md); everything after the
executable is passed through untouched.
"""
from __future__ import annotations

import argparse
import sys

__all__ = ['add_arguments', 'main_passthrough']


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from zros.config import add_session_options
    add_session_options(parser)
    parser.add_argument('package_name', help='package, e.g. demo_nodes')
    parser.add_argument('executable_name', help='executable in the package, e.g. talker')
    parser.add_argument('argv', nargs=argparse.REMAINDER, help='arguments for the executable (and --ros-args ...)')


def main_passthrough(argv: list[str]) -> int:
    from zros.ament_index_python.executables import Executables
    from zros.config import apply_session_options, split_session_options
    from zros.errors import CliError, ZrosError
    options, argv = split_session_options(argv)
    if not argv or argv[0] in ('-h', '--help'):
        print(__doc__.strip())
        print('\nusage: zros run [--connect EP] [--listen EP] [--discovery MODE] [--domain-id N] '
              '[--zenoh-config FILE] PACKAGE EXECUTABLE [args...] [--ros-args ...]')
        print('packages: ' + ', '.join(Executables().packages()))
        return 0
    if len(argv) == 1:
        raise CliError(f"usage: zros run PACKAGE EXECUTABLE [args...]; executables of '{argv[0]}': "
                       + (', '.join(Executables().of(argv[0])) or 'none'))
    package, executable, rest = argv[0], argv[1], argv[2:]
    # The node's signal handling from the start, as zros.init() installs it (zros.signals).
    from zros.signals import install_signal_handlers, signal_received
    install_signal_handlers()
    from zros.import_hook import install
    install()  # any package's nodes may be unmodified rclpy code (`import rclpy`, `from std_msgs.msg ...`)
    entry = Executables().load(package, executable)
    if options:
        apply_session_options(options)
    sys.argv = [executable, *rest]
    try:
        result = entry()
    except KeyboardInterrupt:
        return 130
    except ZrosError:
        raise   # its one line says what happened (e.g. stopped while waiting for the router)
    except Exception:
        if not signal_received():
            raise
        # SIGTERM shut zros down while the node was still being built (before its main's
        # try/except around spin): what failed under it is the stop that was asked for.
        return 0
    return result if isinstance(result, int) else 0
