"""rqt_service_caller: the service caller: a form from the request's definition, as a page of the zros view in the browser.

    zros run rqt_service_caller rqt_service_caller

Serves the view (zros.view.scene) opened on that page, with rqt's other tools as the other
tabs, and logs its URL (http://127.0.0.1:8080/, or the next free port). See docs/rqt.md.
"""
import sys

from zros.view.scene.node import rqt_main as main

__all__ = ['main']

if __name__ == '__main__':
    sys.exit(main(sys.argv))
