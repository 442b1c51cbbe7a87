"""`zros rqt [--page PAGE] [FIELD ...]`: rqt's tools in the browser, as the view's pages.

The same server and page as `zros view` (zros.view.scene), opened on the pages with the wider
panel: topic monitor, plot, service caller, parameters (rqt_reconfigure), graph and console.
`zros run rqt_plot rqt_plot /turtle1/pose/x` and the other rqt commands open one page of it.
"""
from __future__ import annotations

import argparse

__all__ = ['add_arguments', 'cmd_rqt']

_PAGES = {'topics': 'Topics', 'plot': 'Plot', 'services': 'Services', 'parameters': 'Parameters',
          'graph': 'Graph', 'console': 'Console', 'images': 'Images'}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument('fields', nargs='*', metavar='FIELD',
                        help='topic field paths to plot, e.g. /turtle1/pose/x or /turtle1/pose/x:y')
    parser.add_argument('--page', choices=sorted(_PAGES), default=None,
                        help='the page to open on (default: plot when fields are given, else topics)')
    parser.add_argument('--port', type=int, default=None,
                        help='TCP port (default 8080, or the next free one up to 8089; 0 picks any free port)')
    parser.add_argument('--host', default='127.0.0.1',
                        help='address to listen on (default 127.0.0.1: this machine only)')
    parser.set_defaults(handler=cmd_rqt)


def cmd_rqt(args: argparse.Namespace) -> int:
    from zros.cli.view import serve
    from zros.view.scene.node import expand_plot_fields
    page = _PAGES[args.page or ('plot' if args.fields else 'topics')]
    return serve(args, page=page, plot=expand_plot_fields(args.fields))
