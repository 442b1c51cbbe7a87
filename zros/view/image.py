"""sensor_msgs/Image to displayable pixels: the encodings a viewer or a PNG file can show.

Supported encodings (as in sensor_msgs/image_encodings): rgb8, rgba8, bgr8, bgra8, mono8,
8UC1, 8UC3 (taken as bgr, as cv_bridge does), 8UC4 (bgra), mono16 / 16UC1 (the high byte),
and 32FC1 (scaled from its own minimum..maximum to 0..255). Rows may be padded (`step`).
"""
from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ['image_to_array', 'UnsupportedEncoding', 'SUPPORTED_ENCODINGS']

# encoding -> (channels, bytes per channel, channel order to get RGB[A] or None for grey)
_LAYOUTS: dict[str, tuple[int, int, tuple[int, ...] | None]] = {
    'rgb8': (3, 1, (0, 1, 2)),
    'rgba8': (4, 1, (0, 1, 2, 3)),
    'bgr8': (3, 1, (2, 1, 0)),
    'bgra8': (4, 1, (2, 1, 0, 3)),
    '8UC3': (3, 1, (2, 1, 0)),
    '8UC4': (4, 1, (2, 1, 0, 3)),
    'mono8': (1, 1, None),
    '8UC1': (1, 1, None),
    'mono16': (1, 2, None),
    '16UC1': (1, 2, None),
    '32FC1': (1, 4, None),
}
SUPPORTED_ENCODINGS = tuple(_LAYOUTS)


class UnsupportedEncoding(ValueError):
    """The image's encoding (or size fields) cannot be shown."""


def image_to_array(msg: Any) -> np.ndarray:
    """(H, W, 3|4) RGB[A] or (H, W) grey uint8 pixels of a sensor_msgs/Image.

    Raises:
        UnsupportedEncoding: unknown encoding, or data shorter than height x step.
    """
    layout = _LAYOUTS.get(msg.encoding)
    if layout is None:
        raise UnsupportedEncoding(f"cannot show encoding '{msg.encoding}' "
                                  f"(supported: {', '.join(SUPPORTED_ENCODINGS)})")
    channels, size, order = layout
    height, width = int(msg.height), int(msg.width)
    row_bytes = width * channels * size
    step = int(msg.step) or row_bytes
    data = np.frombuffer(memoryview(msg.data).cast('B'), dtype=np.uint8) if not isinstance(
        msg.data, np.ndarray) else np.asarray(msg.data, dtype=np.uint8).reshape(-1)
    if height == 0 or width == 0:
        raise UnsupportedEncoding('empty image (height or width is 0)')
    if step < row_bytes or data.size < step * (height - 1) + row_bytes:
        raise UnsupportedEncoding(f'image data too short: {data.size} bytes for {height} rows of '
                                  f'step {step} ({width} x {msg.encoding})')
    if data.size < step * height:  # last row not padded: pad so that the reshape works
        data = np.concatenate([data, np.zeros(step * height - data.size, dtype=np.uint8)])
    rows = data[:step * height].reshape(height, step)[:, :row_bytes]
    if size == 1:
        pixels = rows.reshape(height, width, channels)
        if order is None:
            return np.ascontiguousarray(pixels[..., 0])
        return np.ascontiguousarray(pixels[..., list(order)])
    if size == 2:
        dtype = '>u2' if msg.is_bigendian else '<u2'
        values = np.ascontiguousarray(rows).view(dtype).reshape(height, width)
        return (values >> 8).astype(np.uint8)
    dtype = '>f4' if msg.is_bigendian else '<f4'
    values = np.ascontiguousarray(rows).view(dtype).reshape(height, width).astype(np.float64)
    finite = np.isfinite(values)
    if not finite.any():
        return np.zeros((height, width), dtype=np.uint8)
    low, high = values[finite].min(), values[finite].max()
    scale = 255.0 / (high - low) if high > low else 0.0
    return np.where(finite, (values - low) * scale, 0).astype(np.uint8)
