"""A minimal PNG writer and reader (numpy + zlib + struct): images out of zros without Pillow.

`encode_png` writes 8-bit grey, grey+alpha, RGB or RGBA, non-interlaced, every row with
filter type "up" (cheap in numpy and good on the flat colours of simulator canvases).
`decode_png` reads what common encoders (browsers' screenshots included) write for 8-bit
images: colour types 0, 2, 3, 4 and 6, all five row filters, no interlacing. It is meant for
tools and tests, not as a general image library.
"""
from __future__ import annotations

import struct
import zlib

import numpy as np

__all__ = ['encode_png', 'decode_png', 'PngError']

_SIGNATURE = b'\x89PNG\r\n\x1a\n'
_COLOR_TYPES = {1: 0, 2: 4, 3: 2, 4: 6}           # channels -> PNG colour type
_CHANNELS = {0: 1, 2: 3, 3: 1, 4: 2, 6: 4}         # PNG colour type -> samples per pixel
_IHDR = struct.Struct('>IIBBBBB')
_LENGTH = struct.Struct('>I')


class PngError(ValueError):
    """The bytes are not a PNG this reader supports."""


def _chunk(kind: bytes, data: bytes) -> bytes:
    return _LENGTH.pack(len(data)) + kind + data + _LENGTH.pack(zlib.crc32(kind + data) & 0xffffffff)


def encode_png(pixels: np.ndarray, *, level: int = 6) -> bytes:
    """PNG bytes for an (H, W), (H, W, 1), (H, W, 3) or (H, W, 4) uint8 array.

    Raises:
        ValueError: the array has another shape or dtype.
    """
    array = np.asarray(pixels)
    if array.dtype != np.uint8:
        raise ValueError(f'encode_png needs uint8 pixels, got {array.dtype}')
    if array.ndim == 2:
        array = array[..., None]
    if array.ndim != 3 or array.shape[2] not in _COLOR_TYPES or 0 in array.shape[:2]:
        raise ValueError(f'encode_png needs an (H, W[, 1|2|3|4]) array, got shape {array.shape}')
    height, width, channels = array.shape
    rows = np.ascontiguousarray(array).reshape(height, width * channels)
    filtered = np.empty((height, width * channels + 1), dtype=np.uint8)
    filtered[:, 0] = 2                                   # filter "up": byte minus the one above
    filtered[0, 1:] = rows[0]
    np.subtract(rows[1:], rows[:-1], out=filtered[1:, 1:])  # uint8 arithmetic wraps mod 256
    header = _IHDR.pack(width, height, 8, _COLOR_TYPES[channels], 0, 0, 0)
    return b''.join((_SIGNATURE, _chunk(b'IHDR', header),
                     _chunk(b'IDAT', zlib.compress(filtered.tobytes(), level)), _chunk(b'IEND', b'')))


def decode_png(data: bytes) -> np.ndarray:
    """An (H, W, C) uint8 array from PNG bytes (C = 1, 2, 3 or 4; palettes come out as RGB[A]).

    Raises:
        PngError: not a PNG, or one this reader does not support (16-bit, interlaced, ...).
    """
    if data[:8] != _SIGNATURE:
        raise PngError('not a PNG file')
    pos, header, palette, alpha, idat = 8, None, None, None, []
    while pos + 8 <= len(data):
        (length,) = _LENGTH.unpack_from(data, pos)
        kind = data[pos + 4:pos + 8]
        body = data[pos + 8:pos + 8 + length]
        pos += 12 + length
        if kind == b'IHDR':
            header = _IHDR.unpack(body)
        elif kind == b'PLTE':
            palette = np.frombuffer(body, dtype=np.uint8).reshape(-1, 3)
        elif kind == b'tRNS':
            alpha = np.frombuffer(body, dtype=np.uint8)
        elif kind == b'IDAT':
            idat.append(body)
        elif kind == b'IEND':
            break
    if header is None:
        raise PngError('PNG without IHDR')
    width, height, depth, color_type, _, _, interlace = header
    if depth != 8 or interlace != 0 or color_type not in _CHANNELS:
        raise PngError(f'unsupported PNG (bit depth {depth}, colour type {color_type}, interlace {interlace})')
    channels = _CHANNELS[color_type]
    stride = width * channels
    raw = zlib.decompress(b''.join(idat))
    if len(raw) != height * (stride + 1):
        raise PngError('PNG image data has the wrong size')
    rows = np.frombuffer(raw, dtype=np.uint8).reshape(height, stride + 1)
    out = np.empty((height, stride), dtype=np.uint8)
    prior = np.zeros(stride, dtype=np.uint8)
    for y in range(height):
        kind, line = rows[y, 0], rows[y, 1:]
        if kind == 0:
            out[y] = line
        elif kind == 1:
            out[y] = _undo_sub(line, channels)
        elif kind == 2:
            out[y] = line + prior
        elif kind in (3, 4):
            out[y] = _undo_average_or_paeth(line, prior, channels, paeth=kind == 4)
        else:
            raise PngError(f'unknown PNG row filter {kind}')
        prior = out[y]
    image = out.reshape(height, width, channels)
    if color_type == 3:
        if palette is None:
            raise PngError('palette PNG without PLTE')
        rgb = palette[image[..., 0]]
        if alpha is not None:
            table = np.full(len(palette), 255, dtype=np.uint8)
            table[:len(alpha)] = alpha[:len(palette)]
            return np.concatenate([rgb, table[image[..., 0]][..., None]], axis=2)
        return rgb
    return image


def _undo_sub(line: np.ndarray, channels: int) -> np.ndarray:
    # Each byte adds the reconstructed byte one pixel to the left: a running sum per channel.
    sums = np.cumsum(line.reshape(-1, channels).astype(np.uint32), axis=0)
    return (sums & 0xff).astype(np.uint8).reshape(-1)


def _undo_average_or_paeth(line: np.ndarray, prior: np.ndarray, channels: int, *, paeth: bool) -> np.ndarray:
    # Each byte depends on the reconstructed byte to its left: plain Python, byte by byte.
    cur = bytearray(line.tobytes())
    up = prior.tobytes()
    for i in range(len(cur)):
        left = cur[i - channels] if i >= channels else 0
        above = up[i]
        if paeth:
            upper_left = up[i - channels] if i >= channels else 0
            p = left + above - upper_left
            pa, pb, pc = abs(p - left), abs(p - above), abs(p - upper_left)
            predictor = left if pa <= pb and pa <= pc else (above if pb <= pc else upper_left)
        else:
            predictor = (left + above) >> 1
        cur[i] = (cur[i] + predictor) & 0xff
    return np.frombuffer(bytes(cur), dtype=np.uint8)
