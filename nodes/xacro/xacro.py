"""`zros run xacro xacro FILE [name:=value ...] [-o OUT]`: expand a xacro file to URDF.

The same program is installed as the `xacro` command, which launch files find with
`FindExecutable(name='xacro')` or `$(command 'xacro ...')`.
"""
from __future__ import annotations

import sys

from zros.urdf.xacro import main as xacro_main


def main(args: list[str] | None = None) -> int:
    return xacro_main(list(sys.argv if args is None else args)[1:])


if __name__ == '__main__':
    sys.exit(main())
