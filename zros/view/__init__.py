"""zros.view: show sensor_msgs/Image topics in a web browser, and write them as PNG.

`ViewServer` serves a small page (shipped in `static/`, no CDN) from the standard library's
HTTP server on localhost; `image_to_array` turns an Image message of the common encodings into
pixels, and zros.image_io writes them as PNG. The CLI verbs `zros view` and `zros image save`,
and the `zros_view view` node, are built on these.
"""
from __future__ import annotations

from zros.view.image import SUPPORTED_ENCODINGS, UnsupportedEncoding, image_to_array
from zros.view.server import DEFAULT_PORT, FrameStore, ViewServer

__all__ = ['ViewServer', 'FrameStore', 'DEFAULT_PORT', 'image_to_array', 'UnsupportedEncoding', 'SUPPORTED_ENCODINGS']
